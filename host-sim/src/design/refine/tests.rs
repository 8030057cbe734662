use super::*;
use crate::design::variables::AttitudeLaw;
use crate::design::variables::LOCAL_DIMENSION;

fn layout() -> Layout {
    Layout {
        law: AttitudeLaw::TiltPriority,
        local: true,
        vertical: true,
        narrow_local: false,
        local_vertical: false,
        turn_over: false,
        local_integral: false,
    }
}

/// A searched optimum at the centre of the box.
fn searched(cost: f64) -> Optimum {
    Optimum {
        x: vec![0.5; layout().dimension()],
        cost,
        evaluations: 960,
    }
}

/// Given a cost whose local coordinates score only with narrowing on (a bowl around 0.2), when
/// the search's optimum is refined, then its global coordinates are kept, its local ones (with
/// the local vertical filters' coordinate added, the vertical channel being apart) move towards
/// the bowl's centre, the narrowing layout is the design's and both budgets are counted.
#[test]
fn a_better_local_regime_is_kept_with_the_global_gains() {
    let cost = |x: &[f64], l: Layout| {
        let local = &x[l.dimension() - l.local_dimension()..];
        let bowl: f64 = local.iter().map(|v| (v - 0.2).powi(2)).sum();
        if l.narrow_local {
            bowl
        } else {
            10.0
        }
    };
    let (best, l, r) = refine_local(&cost, searched(10.0), layout(), 960, 1).unwrap();
    let r = r.unwrap();
    assert!(
        r.kept && l.narrow_local && r.refined < 0.5 * 6.0 * 0.09,
        "{r:?}"
    );
    assert!(l.local_vertical && l.local_dimension() == LOCAL_DIMENSION + 1);
    assert_eq!(best.x.len(), layout().dimension() + 1);
    assert_eq!(best.cost, r.refined);
    let split = layout().dimension() - LOCAL_DIMENSION;
    assert_eq!(&best.x[..split], &searched(10.0).x[..split]);
    assert_eq!(cost(&best.x, l), best.cost);
    assert_eq!(best.evaluations, 960 + r.evaluations);
    let share = (BUDGET_SHARE * 960.0).ceil() as usize;
    assert!(
        r.evaluations <= share && 6 * r.evaluations >= 5 * share,
        "{}",
        r.evaluations
    );
}

/// Given a refinement that finds nothing better, the search's point and layout are the
/// design's, the refinement is reported as not kept, and without a local regime there is none.
#[test]
fn the_search_is_kept_unless_the_refinement_scores_lower() {
    let cost = |_: &[f64], l: Layout| if l.narrow_local { 5.0 } else { 1.0 };
    let (best, l, r) = refine_local(&cost, searched(1.0), layout(), 960, 1).unwrap();
    let r = r.unwrap();
    assert!(!r.kept && r.refined == 5.0 && !l.narrow_local, "{r:?}");
    assert_eq!(best.x, searched(1.0).x);
    assert_eq!(best.cost, 1.0);
    let global = Layout {
        local: false,
        ..layout()
    };
    let (best, l, r) = refine_local(&cost, searched(1.0), global, 960, 1).unwrap();
    assert!(r.is_none() && l == global && best.evaluations == 960);
}
