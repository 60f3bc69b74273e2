//! What a machine's noise costs a code whose ranks wait for each other at every step.
//!
//! Every rank runs the same fixed work per step (a spring force over a list of nearby pairs
//! of points, walked in order: memory, square roots and divisions, like a contact pass),
//! free, each rank on its own, and in lock step, each step ending in a reduction of one
//! number over the ranks, as tumbler's step does. The two modes alternate in pieces of a
//! quarter of a second, so that both meet the same slow changes of the machine's speed;
//! their totals, for each step length asked for, give the ceiling of parallel efficiency
//! that the machine itself sets for steps that long:
//!
//! ```text
//! ceiling = (mean over ranks of the free time) / (lock-step time)
//! ```
//!
//! With every rank's work the same, a code can do no better than this ceiling on that
//! machine, however little it communicates: each step goes at the pace of whichever core
//! is slowest in that step. On a node whose cores keep their speed the ceiling is close to
//! 100 %; on a shared virtual machine it falls as the steps get shorter.
//!
//! ```text
//! mpirun -np 2 target/release/examples/lockstep [STEP_US,...] [SECONDS] [REPS]
//! ```
//!
//! defaults: `400,850,1700,2800,5600` µs, 8 s of each mode per length, 3 repetitions. `benches/lockstep.sh`
//! builds and runs it.

use std::time::Instant;
use tumbler::comm::{Comm, MpiComm};

/// Points per rank: about what one of two ranks holds of the bench bed of `benches/peer.sh`.
const POINTS: usize = 6_744;
/// Listed pairs per point.
const PAIRS_PER_POINT: usize = 6;

/// The points and their pairs, and where the pass stopped at the last step.
struct Work {
    x: Vec<[f64; 3]>,
    f: Vec<[f64; 3]>,
    pairs: Vec<(u32, u32)>,
    cursor: usize,
}

impl Work {
    /// Points on a jittered lattice of spacing 1, each paired with points a little later in
    /// the order (as a cell-sorted list pairs a particle with its neighbours).
    fn new() -> Work {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let side = (POINTS as f64).cbrt().ceil() as usize;
        let x: Vec<[f64; 3]> = (0..POINTS)
            .map(|i| {
                let (a, b, c) = (i % side, (i / side) % side, i / (side * side));
                [
                    a as f64 + 0.1 * next(),
                    b as f64 + 0.1 * next(),
                    c as f64 + 0.1 * next(),
                ]
            })
            .collect();
        let mut pairs = Vec::with_capacity(POINTS * PAIRS_PER_POINT);
        for i in 0..POINTS {
            for _ in 0..PAIRS_PER_POINT {
                let j = (i + 1 + (next() * 64.0) as usize) % POINTS;
                pairs.push((i as u32, j as u32));
            }
        }
        Work {
            f: vec![[0.0; 3]; POINTS],
            x,
            pairs,
            cursor: 0,
        }
    }

    /// One step: `m` pairs' forces, taken on from where the last step stopped, then a tiny
    /// drift of the points (so that the work cannot be hoisted out of the loop).
    fn step(&mut self, m: usize) {
        for f in &mut self.f {
            *f = [0.0; 3];
        }
        for _ in 0..m {
            let (i, j) = self.pairs[self.cursor];
            self.cursor = (self.cursor + 1) % self.pairs.len();
            let (i, j) = (i as usize, j as usize);
            let r = [
                self.x[i][0] - self.x[j][0],
                self.x[i][1] - self.x[j][1],
                self.x[i][2] - self.x[j][2],
            ];
            let d = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
            let s = (1.5 - d) / d;
            for (q, rq) in r.iter().enumerate() {
                self.f[i][q] += s * rq;
                self.f[j][q] -= s * rq;
            }
        }
        for (x, f) in self.x.iter_mut().zip(&self.f) {
            for q in 0..3 {
                x[q] += 1e-12 * f[q];
            }
        }
    }
}

fn main() {
    let Some(universe) = mpi::initialize() else {
        eprintln!("lockstep: MPI could not be initialised");
        std::process::exit(1);
    };
    let comm = MpiComm::new(&universe);
    let args: Vec<String> = std::env::args().skip(1).collect();
    let lengths: Vec<f64> = match args.first() {
        Some(s) => s
            .split(',')
            .map(|t| t.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .unwrap_or_else(|_| {
                usage(&comm, "STEP_US: a list of step lengths in µs, e.g. 400,850")
            }),
        None => vec![400.0, 850.0, 1700.0, 2800.0, 5600.0],
    };
    let seconds: f64 = match args.get(1) {
        Some(s) => s
            .parse()
            .unwrap_or_else(|_| usage(&comm, "SECONDS: a number")),
        None => 8.0,
    };
    let reps: usize = match args.get(2) {
        Some(s) => s
            .parse()
            .unwrap_or_else(|_| usage(&comm, "REPS: a whole number")),
        None => 3,
    };
    let positive = |t: f64| t.is_finite() && t > 0.0;
    if !lengths.iter().all(|&t| positive(t)) || !positive(seconds) || reps == 0 {
        usage(
            &comm,
            "step lengths, seconds and repetitions must be positive",
        );
    }
    let mut work = Work::new();
    // Pairs per µs, measured on rank 0 and agreed on, so that every rank's step is the
    // same work.
    let probe = 2_000_000;
    work.step(probe); // warm the caches first
    let t0 = Instant::now();
    work.step(probe);
    let rate = comm.max_f64(if comm.rank() == 0 {
        probe as f64 / (t0.elapsed().as_secs_f64() * 1e6)
    } else {
        0.0
    });
    if comm.rank() == 0 {
        println!(
            "{} ranks, {POINTS} points and {} pairs per rank; {rate:.0} pairs per µs",
            comm.size(),
            POINTS * PAIRS_PER_POINT
        );
        println!(
            "| step, µs | steps | free, s: mean of ranks (each rank) | lock step, s | ceiling |"
        );
        println!("|---|---|---|---|---|");
    }
    for rep in 0..reps {
        for &len in &lengths {
            let m = (len * rate).round().max(1.0) as usize;
            // the modes alternate in pieces of about a quarter of a second, so that both
            // see the same slow changes of the machine's speed
            let piece = ((0.25e6 / len).round() as usize).max(1);
            let pieces = ((seconds * 1e6 / len / piece as f64).round() as usize).max(1);
            let (mut free, mut lock) = (0.0, 0.0);
            for _ in 0..pieces {
                comm.max_f64(0.0);
                let t = Instant::now();
                for _ in 0..piece {
                    work.step(m);
                }
                free += t.elapsed().as_secs_f64();
                comm.max_f64(0.0);
                let t = Instant::now();
                for _ in 0..piece {
                    work.step(m);
                    comm.max_f64(work.f[0][0]);
                }
                lock += comm.max_f64(t.elapsed().as_secs_f64());
            }
            if let Some(all) = comm.gather_f64(&[free]) {
                let free_mean = all.iter().sum::<f64>() / all.len() as f64;
                let each: Vec<String> = all.iter().map(|t| format!("{t:.3}")).collect();
                println!(
                    "| {len:.0} | {} | {free_mean:.3} ({}) | {lock:.3} | {:.1} % |",
                    pieces * piece,
                    each.join(", "),
                    100.0 * free_mean / lock
                );
            }
        }
        if comm.rank() == 0 && rep + 1 < reps {
            println!("|  |  |  |  |  |");
        }
    }
}

/// Print the usage line with what was wrong, on rank 0, and stop every rank.
fn usage(comm: &MpiComm, why: &str) -> ! {
    if comm.rank() == 0 {
        eprintln!("lockstep: {why}\nusage: mpirun -np N lockstep [STEP_US,...] [SECONDS] [REPS]");
    }
    std::process::exit(2)
}
