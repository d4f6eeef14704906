//! `[schedule]`: the indentation history as segments — approach, load, hold, unload — each
//! moving the controlled variable to a target at a rate (or over a time), or holding it.
//!
//! Under displacement control every target is a depth δ (nm, positive = penetration of the
//! drive); under load control the load/unload targets are loads P (nN, positive compressive)
//! and their rates are load rates (nN/s). An approach always moves the drive (depth) — there
//! is no load to control before contact.

use super::check::Checker;
use super::machine::Control;
use super::quantity::{Amount, Length, Time};
use crate::units::Dimension;
use serde::{Deserialize, Serialize};

/// What a segment does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SegmentKind {
    /// move the drive towards the surface to depth `to` (displacement, in either control)
    Approach,
    /// increase the controlled variable to `to`
    Load,
    /// keep the controlled variable for `time`
    Hold,
    /// decrease the controlled variable to `to`
    Unload,
}

impl SegmentKind {
    /// The name as written in a scene.
    pub fn name(self) -> &'static str {
        match self {
            SegmentKind::Approach => "approach",
            SegmentKind::Load => "load",
            SegmentKind::Hold => "hold",
            SegmentKind::Unload => "unload",
        }
    }
}

/// `[[schedule.segment]]`: one segment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Segment {
    /// `"approach"`, `"load"`, `"hold"` or `"unload"`. Required.
    pub kind: SegmentKind,
    /// Target: a depth (nm) under displacement control and for an approach, a load (nN) for
    /// load/unload under load control. Required except for a hold.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<Amount>,
    /// Rate of the controlled variable: nm/s for depths, nN/s for loads. Give `rate` or
    /// `time`, not both (not for a hold); a `time` is resolved into this rate (|Δ|/time).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<Amount>,
    /// Duration, s: required for a hold; for the other kinds an alternative to `rate`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<Time>,
}

/// `[schedule]`: where the drive starts and the segments in order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Schedule {
    /// Initial depth of the drive, nm: negative means clear of the surface (needed to see
    /// jump-to-contact with adhesion). Default 0 (touching).
    #[serde(default = "default_start")]
    pub start: Length,
    /// The segments, in order. At least one.
    #[serde(default)]
    pub segment: Vec<Segment>,
}

fn default_start() -> Length {
    Length(0.0)
}

/// Totals of a resolved schedule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ScheduleTotals {
    /// total duration, s
    pub duration_s: f64,
    /// largest depth target, nm
    pub max_depth_nm: f64,
    /// largest load target under load control, nN (0 under displacement control)
    pub max_load_nn: f64,
}

impl Segment {
    /// Check a hold (a duration, no target or rate); its duration, s (0 if unusable).
    fn check_hold(&self, c: &mut Checker, key: impl Fn(&str) -> String) -> f64 {
        for (k, present) in [("to", self.to.is_some()), ("rate", self.rate.is_some())] {
            if present {
                c.unused(&key(k), "in a hold (a hold keeps its target; give time)");
            }
        }
        match self.time {
            Some(t) => {
                c.positive(&key("time"), t);
                t.0.max(0.0)
            }
            None => {
                c.bad(key("time"), "is missing: a hold needs its duration");
                0.0
            }
        }
    }

    /// The duration of a moving segment, s, from its rate or its time (the rate resolved from
    /// a time, once, here: the engines take a rate), for a `change` of the controlled
    /// variable of dimension `dim`; None if neither or both are given or they are unusable.
    fn duration(
        &mut self,
        c: &mut Checker,
        key: impl Fn(&str) -> String,
        change: f64,
        dim: Dimension,
        by_load: bool,
    ) -> Option<f64> {
        Some(match (&mut self.rate, self.time) {
            (Some(_), Some(_)) => {
                c.bad(key("rate"), "and time are both given: give one of them");
                return None;
            }
            (None, None) => {
                c.bad(
                    key("rate"),
                    "is missing: give the rate or the time of the segment",
                );
                return None;
            }
            (None, Some(t)) => {
                c.positive(&key("time"), t);
                // the engines take a rate: resolve it from the time once, here
                let r = change.abs() / t.0;
                if t.0 > 0.0 && change != 0.0 && !(r.is_finite() && r > 0.0) {
                    c.bad(
                        key("time"),
                        format!(
                            "{} s is not allowed: moving {} {} in it needs a rate of {r}, not a finite positive number",
                            t.0,
                            change.abs(),
                            dim.internal_unit()
                        ),
                    );
                    return None;
                }
                self.rate = Some(Amount::Number(r));
                t.0
            }
            (Some(rate), None) => {
                let r = if by_load {
                    rate.resolve_per_second(Dimension::Force)
                } else {
                    rate.resolve(Dimension::Rate)
                };
                match r {
                    Ok(r) if r > 0.0 && change != 0.0 && !(change.abs() / r).is_normal() => {
                        c.bad(
                            key("rate"),
                            format!(
                                "{r} is not allowed: the segment would last {} s, not a finite positive time",
                                change.abs() / r
                            ),
                        );
                        return None;
                    }
                    Ok(r) if r > 0.0 => change.abs() / r,
                    Ok(r) => {
                        c.bad(key("rate"), format!("{r} is not allowed: a rate must be positive (its direction comes from the kind)"));
                        return None;
                    }
                    Err(e) => {
                        c.bad(key("rate"), e.to_string());
                        return None;
                    }
                }
            }
        })
    }
}

impl Schedule {
    /// Resolve every target and rate into internal units of the dimension `control` gives
    /// them, checking that the segments follow one another consistently.
    pub(crate) fn check(&mut self, c: &mut Checker, control: Control) -> ScheduleTotals {
        let mut totals = ScheduleTotals {
            duration_s: 0.0,
            max_depth_nm: self.start.0,
            max_load_nn: 0.0,
        };
        if self.segment.is_empty() {
            c.bad(
                "schedule.segment",
                "is empty: give at least one [[schedule.segment]] (kind = \"approach\" | \"load\" | \"hold\" | \"unload\")",
            );
        }
        let mut depth = self.start.0;
        let mut load = 0.0;
        let mut loaded = false;
        for (i, s) in self.segment.iter_mut().enumerate() {
            let key = |k: &str| format!("schedule.segment[{i}].{k}");
            if s.kind == SegmentKind::Hold {
                totals.duration_s += s.check_hold(c, key);
                continue;
            }
            let by_load = control == Control::Load && s.kind != SegmentKind::Approach;
            if s.kind == SegmentKind::Approach && loaded {
                c.bad(
                    key("kind"),
                    "\"approach\" is not allowed after a load segment: approaches come first",
                );
            }
            let (dim, now) = if by_load {
                (Dimension::Force, &mut load)
            } else {
                (Dimension::Length, &mut depth)
            };
            let Some(to) = s.to.as_mut() else {
                c.bad(
                    key("to"),
                    format!(
                        "is missing: a {} segment needs its target ({dim})",
                        s.kind.name()
                    ),
                );
                continue;
            };
            let target = match to.resolve(dim) {
                Ok(v) => v,
                Err(e) => {
                    c.bad(key("to"), e.to_string());
                    continue;
                }
            };
            let change = target - *now;
            let rising = s.kind != SegmentKind::Unload;
            if (rising && change <= 0.0) || (!rising && change >= 0.0) {
                c.bad(
                    key("to"),
                    format!(
                        "{target} {} is not allowed: the {} segment must {} the {} from its current value {} {}",
                        dim.internal_unit(),
                        s.kind.name(),
                        if rising { "increase" } else { "decrease" },
                        if by_load { "load" } else { "depth" },
                        *now,
                        dim.internal_unit()
                    ),
                );
            }
            *now = target;
            if by_load {
                totals.max_load_nn = totals.max_load_nn.max(target);
            } else {
                totals.max_depth_nm = totals.max_depth_nm.max(target);
            }
            loaded |= s.kind == SegmentKind::Load;
            let Some(duration) = s.duration(c, key, change, dim, by_load) else {
                continue;
            };
            totals.duration_s += duration.max(0.0);
        }
        totals
    }
}
