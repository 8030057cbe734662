//! The MAVLink parameter protocol on [`crate::params::PARAMS`]: `PARAM_REQUEST_LIST` streams
//! every `PARAM_VALUE` (one per telemetry call, at most one per [`STREAM_PERIOD_US`], so a list
//! never floods the link), `PARAM_REQUEST_READ` and `PARAM_SET` are answered with one
//! `PARAM_VALUE`.
//!
//! A `PARAM_SET` is taken only while disarmed, and only if the set-up with the new value passes
//! the very checks of boot ([`super::boot::certify_setup`]: certificate of the demo mission, hover
//! controller, box fit with the margin) and the gate says it may fly: the running set-up is
//! certified at every moment, whatever is changed. A refusal leaves everything as it was, is
//! answered with the unchanged value and a STATUSTEXT naming why (the violated condition with
//! both sides), and is logged. Unknown names and indices are answered with a STATUSTEXT only.

use mavlink::dialects::common::{MavParamType, MavSeverity, PARAM_VALUE_DATA, STATUSTEXT_DATA};
use nalgebra::Vector3;

use super::boot::certify_setup;
use super::param_text::{self, Text};
use super::{mahony_dt_cap, BootReport, Event, FlightPipeline, GateFailure};
use crate::config::FlightConfig;
use crate::flight_reference::FlightReference;
use crate::param_store::ParamStore;
use crate::params::{self, ParamError, COUNT, NAME_LEN, PARAMS};
use crate::safety::{FlightState, Supervisor};

/// Shortest time between two streamed `PARAM_VALUE`s \[µs\]: 50 per second, the whole table in
/// 0.4 s, about 1.9 kB/s (37-byte frames, 50 signed): a sixth of a 115 200 baud link, leaving
/// the rest to the state telemetry and the acks.
pub const STREAM_PERIOD_US: u64 = 20_000;

/// Why a parameter change ([`FlightPipeline`]'s `PARAM_SET`, or
/// [`FlightPipeline::restore_params`]) is not taken. Nothing changes on a refusal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamRefusal {
    /// The vehicle is armed (or in the failsafe): parameters change only on the ground,
    /// disarmed.
    Armed,
    /// `param_type` is not `MAV_PARAM_TYPE_REAL32`.
    NotReal32,
    /// The value alone is unusable (non-finite, out of range).
    Value(ParamError),
    /// The candidate set-up fails a condition: the parameters' orderings
    /// ([`params::consistency`]), a parameter controller-core refuses (`lhs` its value, `rhs`
    /// the bound or NaN), a certificate condition or a rotor fit ([`super::gate_check`]).
    Condition(GateFailure),
}

/// Why [`FlightPipeline::restore_params`] restored nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestoreError {
    /// The parameter whose stored value is refused on its own, if the refusal is about one.
    pub name: Option<&'static str>,
    /// Why.
    pub refusal: ParamRefusal,
}

impl FlightPipeline {
    /// `PARAM_REQUEST_LIST`: (re)starts the stream at index 0.
    pub(super) fn param_request_list(&mut self) {
        self.params.stream_next = Some(0);
    }

    /// `PARAM_REQUEST_READ`: by `index` if `>= 0` (the MAVLink rule), else by name `id`;
    /// unknown ones get a STATUSTEXT and no `PARAM_VALUE`.
    pub(super) fn param_request_read(&mut self, id: &[u8; NAME_LEN], index: i16) {
        let found = if index >= 0 {
            Some(index as usize).filter(|&i| i < COUNT)
        } else {
            params::find(id)
        };
        match found {
            Some(i) => self.param_reply(i),
            None if index >= 0 => self.param_text(param_text::unknown_index(index)),
            None => self.param_text(param_text::unknown(id)),
        }
    }

    /// `PARAM_SET`: takes `value` if [`FlightPipeline::try_param_set`] accepts it, and answers
    /// with the (new or unchanged) value; an unknown name gets a STATUSTEXT only.
    pub(super) fn param_set(&mut self, id: &[u8; NAME_LEN], value: f32, real32: bool) {
        let Some(i) = params::find(id) else {
            self.counters.refused_commands = self.counters.refused_commands.saturating_add(1);
            self.event(Event::CommandRefused {
                command: "param_set",
                reason: "unknown parameter",
            });
            self.param_text(param_text::unknown(id));
            return;
        };
        let name = PARAMS[i].name;
        match self.try_param_set(i, value, real32) {
            Ok(()) => {
                self.storage.changed();
                self.event(Event::ParamChanged {
                    name,
                    value: (PARAMS[i].get)(&self.cfg),
                })
            }
            Err(r) => {
                self.counters.refused_commands = self.counters.refused_commands.saturating_add(1);
                let (reason, text) = match r {
                    ParamRefusal::Armed => ("armed", param_text::refused(name, "disarm first")),
                    ParamRefusal::NotReal32 => (
                        "not REAL32",
                        param_text::refused(name, "type must be REAL32"),
                    ),
                    ParamRefusal::Value(ParamError::NotFinite) => {
                        ("not finite", param_text::refused(name, "not finite"))
                    }
                    ParamRefusal::Value(ParamError::OutOfRange { min, max }) => {
                        ("out of range", param_text::out_of_range(name, min, max))
                    }
                    ParamRefusal::Condition(f) => {
                        self.event(Event::ReferenceRefused {
                            condition: f.condition,
                            lhs: f.lhs,
                            rhs: f.rhs,
                        });
                        (
                            "set-up not certified",
                            param_text::condition(name, f.condition, f.lhs, f.rhs),
                        )
                    }
                };
                self.event(Event::CommandRefused {
                    command: name,
                    reason,
                });
                self.param_text(text);
            }
        }
        self.param_reply(i);
    }

    /// Takes `value` for parameter `i` if the vehicle is disarmed, the value is REAL32, finite
    /// and in range, and the candidate set-up passes [`FlightPipeline::check_candidate`].
    fn try_param_set(&mut self, i: usize, value: f32, real32: bool) -> Result<(), ParamRefusal> {
        if self.supervisor.state() != FlightState::Disarmed {
            return Err(ParamRefusal::Armed);
        }
        if !real32 {
            return Err(ParamRefusal::NotReal32);
        }
        let mut candidate = self.cfg;
        PARAMS[i]
            .apply(&mut candidate, value)
            .map_err(ParamRefusal::Value)?;
        let report = self.check_candidate(&candidate)?;
        self.take_candidate(candidate, report);
        Ok(())
    }

    /// Restores the parameters stored in `store` (those it has; the others keep their built
    /// values), all at once, while disarmed (at boot): the candidate set-up with every stored
    /// value must pass the checks of a `PARAM_SET`, or nothing is restored. Returns how many
    /// values were taken. Errors: [`RestoreError`], naming the first refused value or the
    /// failed condition.
    pub fn restore_params<S: ParamStore>(&mut self, store: &S) -> Result<usize, RestoreError> {
        if self.supervisor.state() != FlightState::Disarmed {
            return Err(RestoreError {
                name: None,
                refusal: ParamRefusal::Armed,
            });
        }
        let mut candidate = self.cfg;
        let mut restored = 0;
        for (i, p) in PARAMS.iter().enumerate() {
            if let Some(v) = store.load(i) {
                p.apply(&mut candidate, v).map_err(|e| RestoreError {
                    name: Some(p.name),
                    refusal: ParamRefusal::Value(e),
                })?;
                restored += 1;
            }
        }
        let report = self
            .check_candidate(&candidate)
            .map_err(|refusal| RestoreError {
                name: None,
                refusal,
            })?;
        self.take_candidate(candidate, report);
        Ok(restored)
    }

    /// `MAV_CMD_PREFLIGHT_STORAGE` reset, while disarmed: flies the set-up the pipeline was built
    /// with (which boot accepted) and emits [`Event::ParamsReset`] for the store. Errors: why
    /// not (armed; the built set-up no longer certifies, which cannot happen: same checks).
    pub(super) fn reset_params(&mut self) -> Result<(), &'static str> {
        if self.supervisor.state() != FlightState::Disarmed {
            return Err("disarm first");
        }
        let built = self.built;
        let report =
            certify_setup(&built, &self.mixer).map_err(|_| "built set-up not certified")?;
        self.take_candidate(built, report);
        self.storage.changed();
        self.event(Event::ParamsReset);
        Ok(())
    }

    /// The checks every parameter change runs on the whole candidate set-up: the orderings
    /// ([`params::consistency`]), then boot's [`certify_setup`] and its gate. Returns the
    /// candidate's boot report.
    fn check_candidate(&self, candidate: &FlightConfig) -> Result<BootReport, ParamRefusal> {
        params::consistency(candidate).map_err(ParamRefusal::Condition)?;
        let report = certify_setup(candidate, &self.mixer).map_err(|e| {
            let r = crate::report::refusal(&e);
            ParamRefusal::Condition(GateFailure {
                condition: r.name,
                lhs: r.value as f32,
                rhs: if r.high.is_finite() {
                    r.high as f32
                } else {
                    f32::NAN
                },
            })
        })?;
        report.gate.map_err(ParamRefusal::Condition)?;
        Ok(report)
    }

    /// Flies `candidate` from now on (disarmed): its configuration and boot report (what
    /// arming checks and the banner shows), the supervisor's timings and the reference's
    /// filter. The mixer stays: the rotors are not parameters.
    fn take_candidate(&mut self, candidate: FlightConfig, report: BootReport) {
        self.cfg = candidate;
        self.mahony_dt_cap = mahony_dt_cap(&candidate);
        self.report = report;
        // Disarmed: a fresh supervisor is in the same state, with the new timings.
        self.supervisor = Supervisor::new(candidate.safety);
        // Arming rebuilds the reference at the vehicle's pose; until then it only has to carry
        // the new bandwidth, like the one built at boot.
        self.reference = FlightReference::new(
            candidate.reference.smoothing_rate,
            Vector3::zeros(),
            0.0,
            self.table,
            candidate.mission,
        );
    }

    /// Queues a `PARAM_VALUE` of parameter `i`, or counts it dropped.
    fn param_reply(&mut self, i: usize) {
        if self.params.replies.push_back(i as u8).is_err() {
            self.counters.replies_dropped = self.counters.replies_dropped.saturating_add(1);
        }
    }

    /// Queues a STATUSTEXT, or counts it dropped.
    fn param_text(&mut self, text: Text) {
        if self.params.texts.push_back(text).is_err() {
            self.counters.replies_dropped = self.counters.replies_dropped.saturating_add(1);
        }
    }

    /// Writes pending parameter texts and replies and at most one streamed `PARAM_VALUE` into
    /// `out`. Returns the bytes written and whether everything due was written (false: out of
    /// room; the rest waits, whole, for the next call).
    pub(super) fn param_telemetry(&mut self, now_us: u64, out: &mut [u8]) -> (usize, bool) {
        let mut n = 0;
        while let Some(t) = self.params.texts.front() {
            let m = STATUSTEXT_DATA {
                severity: MavSeverity::MAV_SEVERITY_WARNING,
                text: t.field().into(),
            };
            match self.put(&m, &mut out[n..]) {
                0 => return (n, false),
                k => n += k,
            }
            self.params.texts.pop_front();
        }
        while let Some(&i) = self.params.replies.front() {
            match self.put(&self.param_value(i as usize), &mut out[n..]) {
                0 => return (n, false),
                k => n += k,
            }
            self.params.replies.pop_front();
        }
        if let Some(i) = self.params.stream_next {
            let due = self
                .params
                .stream_sent_us
                .is_none_or(|t| now_us >= t.saturating_add(STREAM_PERIOD_US));
            if due {
                match self.put(&self.param_value(i as usize), &mut out[n..]) {
                    0 => return (n, false),
                    k => n += k,
                }
                self.params.stream_sent_us = Some(now_us);
                let next = i as usize + 1;
                self.params.stream_next = (next < COUNT).then_some(next as u8);
            }
        }
        (n, true)
    }

    /// The `PARAM_VALUE` of parameter `i` (< [`COUNT`]) with its current value.
    fn param_value(&self, i: usize) -> PARAM_VALUE_DATA {
        let p = &PARAMS[i];
        PARAM_VALUE_DATA {
            param_value: (p.get)(&self.cfg),
            param_count: COUNT as u16,
            param_index: i as u16,
            param_id: p.id().into(),
            param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
        }
    }
}
