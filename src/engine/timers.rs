//! Wall-clock time per phase of the step, printed as a table at the end of a run.

use std::time::Instant;

/// The phases of a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Half kicks and drift.
    Integrate,
    /// Pair contacts.
    Pairs,
    /// Wall contacts and gravity.
    Walls,
    /// Cell binning and pair-list build.
    Neighbor,
    /// Migration, halo build, ghost updates and the rebuild decision.
    Comm,
    /// Gather stage and output.
    Output,
}

/// Every phase, in table order.
pub const PHASES: [Phase; 6] = [
    Phase::Integrate,
    Phase::Pairs,
    Phase::Walls,
    Phase::Neighbor,
    Phase::Comm,
    Phase::Output,
];

impl Phase {
    /// Name shown in the table.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Integrate => "integrate",
            Phase::Pairs => "contacts",
            Phase::Walls => "walls+gravity",
            Phase::Neighbor => "neighbour build",
            Phase::Comm => "halo/migration",
            Phase::Output => "gather/output",
        }
    }
}

/// Accumulated seconds per phase.
#[derive(Debug, Clone, Default)]
pub struct Timers {
    secs: [f64; 6],
}

impl Timers {
    /// Run `f`, charging its time to `phase`.
    #[inline]
    pub fn time<R>(&mut self, phase: Phase, f: impl FnOnce() -> R) -> R {
        let t0 = Instant::now();
        let r = f();
        self.secs[phase as usize] += t0.elapsed().as_secs_f64();
        r
    }

    /// Charge `secs` seconds to `phase`.
    pub fn add(&mut self, phase: Phase, secs: f64) {
        self.secs[phase as usize] += secs;
    }

    /// Seconds spent in `phase`.
    pub fn get(&self, phase: Phase) -> f64 {
        self.secs[phase as usize]
    }

    /// Total seconds.
    pub fn total(&self) -> f64 {
        self.secs.iter().sum()
    }
}
