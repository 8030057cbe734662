//! What one law's search and the finish of its design share ([`Setup`]): the options, the
//! vehicle, the reference certified, the runs' settings, and the scoring of a point on them.

use std::time::Instant;

use anyhow::{Context as _, Result};
use controller_core::TrajectoryConstants;

use super::{load_reference, score, score_mapped, with_idle_airmode, Scored};
use crate::design::authority::{PositionLaw, RotorSet};
use crate::design::feasibility::*;
use crate::design::flight::FlightSettings;
use crate::design::options::*;
use crate::design::reference::{largest_certifiable_scale, Reference};
use crate::design::thrust::ThrustDesign;
use crate::design::tight::SEARCH_BOXES;
use crate::design::variables::{map, AttitudeLaw, Choices, Context, Layout, Mapped};
use crate::design::vehicle::DesignVehicle;
use crate::model::scenario::ControllerConfig;

/// What one law's search and the finish of its design share: the options, the vehicle, the
/// reference certified (scaled when the requested one cannot be) and the runs' settings.
pub(super) struct Setup {
    pub(super) o: DesignOptions,
    pub(super) law: AttitudeLaw,
    /// When this law's design started (for the report's wall time).
    pub(super) started: Instant,
    pub(super) vehicle: DesignVehicle,
    pub(super) set: RotorSet,
    /// The reference asked for (the heading held when the fallback asks).
    pub(super) asked: Reference,
    /// The reference certified: `asked` slowed down by `scale` when it binds.
    pub(super) reference: Reference,
    pub(super) scale: f64,
    /// Why `asked` could not be certified, if it could not.
    pub(super) binding: Option<String>,
    pub(super) constants: TrajectoryConstants<f64>,
    pub(super) period: f64,
    pub(super) settings: FlightSettings,
}

impl Setup {
    /// Loads and checks `o`'s vehicle and reference for attitude law `law`, slowing the
    /// reference down until it can be certified. Errors: as [`run_design`], except writing.
    pub(super) fn new(o: &DesignOptions, law: AttitudeLaw) -> Result<Self> {
        let started = Instant::now();
        let vehicle = DesignVehicle::load(&o.vehicle)?;
        let set = refuse_impossible(&vehicle)?;
        let (asked, period) = load_reference(o.reference.as_ref())?;
        // The fallback's first step certifies the same path with the heading held (run_design
        // only asks for it when the requested heading swings).
        let requested = match o.heading_held {
            Some(_) => asked.heading_held().unwrap_or_else(|| asked.clone()),
            None => asked.clone(),
        };
        if let Some(spec) = o.integral.as_ref() {
            refuse_uncoverable(&vehicle, &set, spec)?;
        }
        let position = position_law(o);
        let binding = binding_condition(
            &vehicle,
            &set,
            (o.margin, law, o.bounds, o.fit),
            position,
            &requested,
        );
        let (reference, scale) = match &binding {
            None => (requested.clone(), 1.0),
            Some(why) => {
                eprintln!(
                    "design ({}): the requested reference cannot be certified on {}: {why}",
                    law.name(),
                    vehicle.name
                );
                let s = largest_certifiable_scale(&requested, |r| {
                    binding_condition(
                        &vehicle,
                        &set,
                        (o.margin, law, o.bounds, o.fit),
                        position,
                        r,
                    )
                    .is_none()
                })
                .with_context(|| {
                    format!(
                        "{}: no design can be certified for {} even with the reference slowed down \
                         (frequencies x 2^-30): {why}",
                        vehicle.origin, vehicle.name
                    )
                })?;
                eprintln!(
                    "design ({}): designing for the same reference slowed down by {s:.4} (frequencies x {s:.4})",
                    law.name()
                );
                (requested.scaled(s), s)
            }
        };
        ThrustDesign::check_flown(o.thrust).map_err(anyhow::Error::msg)?;
        let settings = FlightSettings {
            duration_s: o.duration_s,
            controller_period_s: period,
            controller: ControllerConfig {
                thrust: o.thrust,
                ..ControllerConfig::default()
            },
        };
        Ok(Self {
            o: o.clone(),
            law,
            started,
            constants: reference.constants(),
            vehicle,
            set,
            asked,
            reference,
            scale,
            binding,
            period,
            settings,
        })
    }

    /// The search's context (borrows the set-up).
    pub(super) fn ctx(&self) -> Context<'_> {
        Context {
            vehicle: &self.vehicle.body,
            constants: &self.constants,
            rotors: &self.set,
            margin: self.o.margin,
            fit: self.o.fit,
            bounds: self.o.bounds,
            position: position_law(&self.o),
            speed_limit: self.o.speed_limit,
        }
    }

    /// The objective of point `x` of the unit box under `layout` (the refusal's cost when it
    /// cannot be certified or flown), with the search's box budget.
    pub(super) fn cost_in(&self, x: &[f64], layout: Layout) -> f64 {
        match score(
            &self.vehicle,
            (&self.ctx(), layout),
            &self.reference,
            (self.settings, SEARCH_BOXES),
            x,
            false,
        ) {
            Ok(s) => s.evaluation.cost,
            Err(c) => c,
        }
    }

    /// The objective of gains already mapped (`mapped`; the refusal's cost when they cannot be
    /// certified or flown), with the search's box budget: how the refinements that change
    /// gains outside the unit box score them.
    pub(super) fn cost_of(&self, mapped: Mapped) -> f64 {
        match score_mapped(
            &self.vehicle,
            &self.ctx(),
            &self.reference,
            (self.settings, SEARCH_BOXES),
            mapped,
            false,
        ) {
            Ok(s) => s.evaluation.cost,
            Err(c) => c,
        }
    }

    /// Point `x` under `layout` flown for the report ([`Self::final_score_mapped`]). Errors: `x`
    /// cannot be mapped, certified and flown (a bug: the search only keeps points that can).
    pub(super) fn final_score(&self, x: &[f64], layout: Layout) -> Result<Scored> {
        let mapped = map(&self.ctx(), &Choices::from_unit(x, layout)).ok_or_else(|| {
            anyhow::anyhow!("the best design found could not be mapped to gains (bug)")
        })?;
        self.final_score_mapped(mapped)
    }

    /// Gains `mapped` flown for the report (traced), with the final tight bounds' default
    /// budget (never looser than the search's), and with airmode's margin above the rotors'
    /// least thrust where that scores lower ([`with_idle_airmode`]). Errors: they cannot be
    /// certified and flown (a bug: the search only keeps gains that can).
    pub(super) fn final_score_mapped(&self, mapped: Mapped) -> Result<Scored> {
        let final_boxes = crate::bounds::tight::TightOptions::default().max_boxes;
        let ctx = self.ctx();
        // `low`: airmode's margin above the rotors' least thrust (`None`: the design margin).
        let flown = |low: Option<f64>| {
            let settings = FlightSettings {
                controller: ControllerConfig {
                    airmode_low_margin: low,
                    ..self.settings.controller
                },
                ..self.settings
            };
            score_mapped(
                &self.vehicle,
                &ctx,
                &self.reference,
                (settings, final_boxes),
                mapped,
                true,
            )
        };
        let best = flown(None).map_err(|_| {
            anyhow::anyhow!("the best design found could not be certified and flown (bug)")
        })?;
        Ok(with_idle_airmode(best, |low| flown(Some(low)).ok()))
    }
}

/// The position law's options that enter the bounds, from `o`.
fn position_law(o: &DesignOptions) -> PositionLaw<'_> {
    PositionLaw {
        integral: o.integral.as_ref(),
        shape: o.position_saturation,
        lemma1: o.lemma1,
        vertical: None,
        heading: o.heading.compensator(),
    }
}
