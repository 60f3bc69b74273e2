//! Thermo lines: the run's state in columns every `output.thermo_every` rotations, as
//! LAMMPS' thermo output prints it, in the log and on stderr.
//!
//! ```text
//! thermo: KE_trans, KE_rot in J; MaxOverlap over the smaller diameter; Repose in degrees; ...
//!       Step  Rotations  Particles     KE_trans       KE_rot  Contacts  MaxOverlap  Repose  Airborne    PSteps/s
//!          0     0.0000       2314  0.00000e+00  0.00000e+00      4520  1.2345e-03   31.20    0.0013         nan
//! ```
//! Every column but the rate is the same on any number of ranks (`engine::thermo`).

use crate::case::{Case, Family};
use crate::diag::surface::SurfaceGauge;
use crate::diag::AxialBins;
use crate::engine::thermo::{measure, ThermoState};
use crate::engine::{Sim, PHASES};
use std::time::Instant;

/// Names of the columns, in order.
pub const COLUMNS: [&str; 10] = [
    "Step",
    "Rotations",
    "Particles",
    "KE_trans",
    "KE_rot",
    "Contacts",
    "MaxOverlap",
    "Repose",
    "Airborne",
    "PSteps/s",
];

/// The thermo schedule and what a line needs from the previous one.
#[derive(Debug)]
pub struct Thermo {
    gauge: SurfaceGauge,
    every: u64,
    energy_unit: &'static str,
    /// Wall clock, step, rebuilds and phase times at the previous line.
    last: Option<(Instant, u64, u64, Vec<f64>)>,
}

impl Thermo {
    /// The thermo lines of `case`, every `every` steps, with the surface measured on the
    /// run's axial slices `bins`.
    pub fn new(case: &Case, bins: &AxialBins, every: u64) -> Self {
        let radius = 0.5 * case.drum.diameter;
        Thermo {
            gauge: SurfaceGauge::new(
                bins.nz,
                bins.z0,
                bins.width,
                radius,
                case.d_max(),
                case.drum.omega,
            ),
            every: every.max(1),
            energy_unit: match case.model.family {
                Family::Rapaport => "reduced units (m d^2 / t^2 of Rapaport's section III)",
                Family::SpringDashpot => "J",
            },
            last: None,
        }
    }

    /// Whether step `step` gets a line (`last`: the run's last step, which always does).
    pub fn due(&self, step: u64, last: u64) -> bool {
        step.is_multiple_of(self.every) || step == last
    }

    /// The two header lines: units, then column names.
    pub fn header(&self) -> [String; 2] {
        [
            format!(
                "thermo: KE_trans, KE_rot in {}; MaxOverlap over the smaller diameter of the pair; \
                 Repose the whole-drum dynamic angle of repose in degrees; Airborne the fraction of \
                 the particles touching nothing; PSteps/s particle-steps per second since the \
                 previous line (nan on the first)",
                self.energy_unit
            ),
            format!(
                "{:>10} {:>10} {:>10} {:>12} {:>12} {:>9} {:>11} {:>7} {:>9} {:>11}",
                COLUMNS[0],
                COLUMNS[1],
                COLUMNS[2],
                COLUMNS[3],
                COLUMNS[4],
                COLUMNS[5],
                COLUMNS[6],
                COLUMNS[7],
                COLUMNS[8],
                COLUMNS[9]
            ),
        ]
    }

    /// Measure `sim` (every rank together) and, on rank 0 (`root`), log the line (with the
    /// header before the first one) and the detail behind it at debug level.
    pub fn report(&mut self, sim: &Sim, root: bool) {
        let t = measure(sim, &self.gauge);
        if !root {
            return;
        }
        let now = Instant::now();
        let times: Vec<f64> = PHASES.iter().map(|&ph| sim.timers.get(ph)).collect();
        let rate = match &self.last {
            Some((t0, s0, rebuilds0, times0)) => {
                let steps = t.step - s0;
                let secs = now.duration_since(*t0).as_secs_f64().max(1e-9);
                let phases: Vec<String> = PHASES
                    .iter()
                    .zip(times.iter().zip(times0))
                    .map(|(ph, (a, b))| format!("{} {:.2} s", ph.name(), a - b))
                    .collect();
                log::debug!(
                    "steps {s0}-{}: {} neighbour-list rebuilds, {:.1} s; {}",
                    t.step,
                    sim.rebuilds - rebuilds0,
                    secs,
                    phases.join(", ")
                );
                t.particles as f64 * steps as f64 / secs
            }
            None => {
                for h in self.header() {
                    log::info!("{h}");
                }
                f64::NAN
            }
        };
        log::info!("{}", line(&t, sim.rotations(), rate));
        self.last = Some((now, t.step, sim.rebuilds, times));
    }
}

/// One thermo line.
pub fn line(t: &ThermoState, rotations: f64, rate: f64) -> String {
    format!(
        "{:>10} {:>10.4} {:>10} {:>12.5e} {:>12.5e} {:>9} {:>11.4e} {:>7.2} {:>9.4} {:>11.4e}",
        t.step,
        rotations,
        t.particles,
        t.ke_trans,
        t.ke_rot,
        t.contacts,
        t.max_overlap,
        t.repose_deg,
        t.airborne,
        rate
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_has_one_number_under_each_column() {
        let t = ThermoState {
            step: 1200,
            particles: 2314,
            ke_trans: 1.5e-4,
            ke_rot: 2.5e-6,
            contacts: 5123,
            max_overlap: 3.2e-3,
            repose_deg: f64::NAN,
            airborne: 0.0125,
        };
        let l = line(&t, 1.25, f64::NAN);
        let words: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
        assert_eq!(words.len(), COLUMNS.len());
        assert_eq!(words[0], 1200.0);
        assert_eq!(words[3], 1.5e-4);
        assert!(words[7].is_nan() && words[9].is_nan());
        assert_eq!(words[8], 0.0125);
    }
}
