//! `design.md`'s lines on the attempts behind a design: the fallbacks taken (the requested path
//! with the heading held, the velocity-limited feedback on longer runs) and whether the
//! requested reference is certified as is or slowed down (docs/design.md, "The fallback" and
//! "When the reference cannot be certified"); the local regime's refinement after the search
//! (docs/envelope-design.md).

use std::fmt::Write as _;

use super::super::report::Report;

/// Appends the lines to `s`.
pub(super) fn write(s: &mut String, r: &Report) {
    if let Some(why) = &r.fallback {
        let _ = writeln!(
            s,
            "**Fallback:** {why}; this design flies the velocity-limited position feedback on \
             {} s runs (docs/velocity-limit.md; the wall time above counts both attempts).\n",
            r.duration_s
        );
    }
    if let Some(why) = &r.reference.heading_held {
        let _ = writeln!(
            s,
            "**Heading held:** for the requested reference {why}; this design is certified for \
             the same path with the heading held at its initial value (the wall time above \
             counts both attempts; docs/design.md).\n"
        );
    }
    if r.reference.scaled {
        let _ = writeln!(
            s,
            "**THE REQUESTED REFERENCE CANNOT BE CERTIFIED ON THIS VEHICLE.** Binding: {}.\n\n\
             **This design is certified for the same reference slowed down: every frequency x {:.4}.**\n",
            r.reference.binding.as_deref().unwrap_or("?"),
            r.reference.scale
        );
    } else if r.reference.heading_held.is_none() {
        let _ = writeln!(s, "The requested reference is certified as is.\n");
    }
    if let Some(f) = &r.local_refinement {
        let _ = writeln!(
            s,
            "Local regime refined after the search (docs/envelope-design.md, \"What `design` \
             searches\"): the global gains held, {} more evaluations over the local regime's \
             variables with envelopes narrowed where nothing fits; objective {:.3} -> {:.3}: {}.\n",
            f.evaluations,
            f.searched,
            f.refined,
            if f.kept {
                "kept, this design's local regime"
            } else {
                "not kept, the search's design scores lower"
            }
        );
    }
    if let Some(f) = &r.turn_over_refinement {
        let _ = writeln!(
            s,
            "Turn-over term refined after the search (docs/turn-over.md, \"In `design`\"): the \
             position loop held, {} more evaluations over the turn-over share `M_t / iota_1` and \
             the attitude variables, from the design without the term; objective {:.3} -> {:.3}: \
             {}.\n",
            f.evaluations,
            f.searched,
            f.refined,
            if f.kept {
                "kept, this design's attitude law"
            } else {
                "not kept, the design without the term scores lower"
            }
        );
    }
    if let Some(f) = &r.local_loop_refinement {
        let _ = writeln!(
            s,
            "Local position loop polished last (docs/envelope-design.md, \"What `design` \
             searches\"): everything else held, {} more evaluations on a grid over the local \
             natural frequency and damping; objective {:.3} -> {:.3}: {}.\n",
            f.evaluations,
            f.searched,
            f.refined,
            if f.kept {
                "kept, this design's local loop"
            } else {
                "not kept, the design before scores lower"
            }
        );
    }
    if let Some(f) = &r.local_agility_refinement {
        let _ = writeln!(
            s,
            "Local regime's agility refined last (docs/envelope-design.md, \"What `design` \
             searches\"): every global gain held, {} more evaluations over the local filters, \
             level and braking, the local position loop, the local attitude law, the envelope \
             and the local vertical channel; objective {:.3} -> {:.3}: {}.\n",
            f.evaluations,
            f.searched,
            f.refined,
            if f.kept {
                "kept, this design's local regime"
            } else {
                "not kept, the design before scores lower"
            }
        );
    }
}
