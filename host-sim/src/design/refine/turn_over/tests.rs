use super::*;
use crate::design::variables::{AttitudeLaw, Choices, TILT_DIMENSION};

fn layout(law: AttitudeLaw) -> Layout {
    Layout {
        law,
        local: true,
        vertical: true,
        narrow_local: true,
        local_vertical: true,
        turn_over: false,
        local_integral: false,
    }
}

/// A searched optimum at `0.4` in every coordinate, with cost `cost`.
fn searched(law: AttitudeLaw, cost: f64) -> Optimum {
    Optimum {
        x: vec![0.4; layout(law).dimension()],
        cost,
        evaluations: 960,
    }
}

/// Given a cost that only the turn-over share and the attitude variables lower (a bowl around
/// 0.3 in each, scored with the share searched), when the search's optimum is refined, then the
/// share is inserted right after the law's variables, only the refined coordinates move, the
/// design's layout searches the share, its choices read it back, and both budgets count.
#[test]
fn a_better_turn_over_design_is_kept_with_the_rest_of_the_search() {
    let law = AttitudeLaw::TiltPriority;
    let cost = |x: &[f64], l: Layout| {
        if !l.turn_over {
            return 10.0;
        }
        ATTITUDE_VARIABLES
            .iter()
            .chain([&TURN_OVER])
            .map(|&i| (x[i] - 0.3).powi(2))
            .sum()
    };
    let (best, l, r) = refine_turn_over(&cost, searched(law, 10.0), layout(law), 960, 1).unwrap();
    let r = r.unwrap();
    assert!(r.kept && l.turn_over && r.refined < 0.1, "{r:?}");
    assert_eq!(best.x.len(), layout(law).dimension() + 1);
    assert_eq!(l.dimension(), best.x.len());
    assert_eq!(best.cost, r.refined);
    assert_eq!(cost(&best.x, l), best.cost);
    for (i, &v) in best.x.iter().enumerate() {
        let refined = ATTITUDE_VARIABLES.contains(&i) || i == TURN_OVER;
        assert!(refined || v == 0.4, "coordinate {i} moved to {v}");
    }
    let share = Choices::from_unit(&best.x, l)
        .tilt
        .and_then(|t| t.turn_over_share)
        .unwrap();
    assert!((share - 0.5 * best.x[TURN_OVER]).abs() < 1e-12);
    assert_eq!(best.evaluations, 960 + r.evaluations);
    assert!(r.evaluations <= (BUDGET_SHARE * 960.0).ceil() as usize);
}

/// Given a refinement that finds nothing better, the search's point and layout are the
/// design's; with the paper's law, a layout that already searches the share, or a search whose
/// design misses a constraint, there is none.
#[test]
fn the_search_is_kept_unless_the_turn_over_refinement_scores_lower() {
    let law = AttitudeLaw::TiltPriority;
    let cost = |_: &[f64], l: Layout| if l.turn_over { 5.0 } else { 1.0 };
    let (best, l, r) = refine_turn_over(&cost, searched(law, 1.0), layout(law), 960, 1).unwrap();
    let r = r.unwrap();
    assert!(!r.kept && r.refined == 5.0 && !l.turn_over, "{r:?}");
    assert_eq!(best.x, searched(law, 1.0).x);
    assert_eq!(best.x.len(), layout(law).dimension());
    let paper = AttitudeLaw::Paper;
    let (best, l, r) =
        refine_turn_over(&cost, searched(paper, 1.0), layout(paper), 960, 1).unwrap();
    assert!(r.is_none() && l == layout(paper) && best.evaluations == 960);
    let with = Layout {
        turn_over: true,
        local_integral: false,
        ..layout(law)
    };
    assert_eq!(with.attitude_dimension(), TILT_DIMENSION + 1);
    let already = Optimum {
        x: vec![0.4; with.dimension()],
        cost: 1.0,
        evaluations: 960,
    };
    let (_, l, r) = refine_turn_over(&cost, already, with, 960, 1).unwrap();
    assert!(r.is_none() && l == with);
    let missed = searched(law, PENALTY + 1.0);
    let (best, l, r) = refine_turn_over(&cost, missed, layout(law), 960, 1).unwrap();
    assert!(r.is_none() && l == layout(law) && best.evaluations == 960);
}
