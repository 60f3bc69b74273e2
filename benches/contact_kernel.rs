//! The pair pass alone (`engine::forces`), touching pairs per second: the scalar reference
//! laws against the batched pass on each instruction set this CPU has, for the thesis'
//! linear spring-dashpot law with Cundall-Strack histories (with the model's normal
//! coefficients, and with each pair's own) and for Rapaport's law.
//!
//!   cargo bench --bench contact_kernel
//!
//! The bed is a jittered simple-cubic lattice compressed so that about a quarter of the
//! listed pairs touch, as in a settled drum; the histories are those the pass itself leaves
//! (a few passes are run before timing).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumbler::engine::forces::{pair_forces_with, Isa};
use tumbler::engine::neighbor::{Grid, NeighborList};
use tumbler::particles::{ParticleState, Particles};
use tumbler::physics::cohesion::CohesionLaw;
use tumbler::physics::normal::NormalLaw;
use tumbler::physics::rolling::RollingLaw;
use tumbler::physics::tangential::TangentialLaw;
use tumbler::physics::{ContactLaw, Materials};

/// `side^3` particles of diameter about `d` on a lattice of spacing `0.97 d`, jittered.
fn lattice(side: usize, d: f64, mat: &Materials) -> Particles {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut p = Particles::default();
    let mut id = 0;
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                let mut jit = || rng.gen_range(-0.04..0.04) * d;
                let x = [
                    (i as f64 * 0.97) * d + jit(),
                    (j as f64 * 0.97) * d + jit(),
                    (k as f64 * 0.97) * d + jit(),
                ];
                let v = [jit() * 100.0, jit() * 100.0, jit() * 100.0];
                let w = [jit() * 2e3, jit() * 2e3, jit() * 2e3];
                let dia = d * rng.gen_range(0.9..1.1);
                let s = ParticleState::new(id, (id % 2) as u8, dia, x, v, w);
                p.push_owned(&s, mat);
                id += 1;
            }
        }
    }
    p
}

fn case(name: &str) -> tumbler::case::Case {
    let path = format!("{}/tests/cases/{name}", env!("CARGO_MANIFEST_DIR"));
    tumbler::case::parse_case(&std::fs::read_to_string(path).unwrap(), name).unwrap()
}

fn bench_law(c: &mut Criterion, name: &str, law: ContactLaw, mat: &Materials, d: f64) {
    let side = 28;
    let mut p = lattice(side, d, mat);
    let reach = 1.2 * law.cutoff(1.1 * d, 1.1 * d);
    let hi = side as f64 * d;
    let grid = Grid::over([-d; 3], [hi; 3], reach);
    let mut nl = NeighborList::default();
    nl.build(&p, &grid, 0.2 * reach, &law);
    for _ in 0..3 {
        pair_forces_with(Isa::Reference, &mut p, &mut nl, &law, mat, None, 1.0);
    }
    let touching = nl
        .pairs
        .iter()
        .filter(|&&(a, b)| {
            let (a, b) = (a as usize, b as usize);
            let r2: f64 = (0..3).map(|k| (p.x[a][k] - p.x[b][k]).powi(2)).sum();
            let rc = law.cutoff(p.diameter[a], p.diameter[b]);
            r2 < rc * rc
        })
        .count();
    eprintln!(
        "{name}: {} particles, {} listed pairs, {touching} touching",
        p.len(),
        nl.pairs.len()
    );
    let mut g = c.benchmark_group(name);
    g.throughput(Throughput::Elements(touching as u64));
    for isa in [Isa::Reference, Isa::Base, Isa::Avx2, Isa::Avx512] {
        if isa > Isa::of_cpu() {
            continue;
        }
        g.bench_with_input(
            BenchmarkId::from_parameter(isa.name()),
            &isa,
            |bch, &isa| bch.iter(|| pair_forces_with(isa, &mut p, &mut nl, &law, mat, None, 1.0)),
        );
    }
    g.finish();
}

fn kernels(c: &mut Criterion) {
    let sd = case("sd_capped.toml");
    let mat = Materials::new(&sd);
    let plain = ContactLaw {
        normal: NormalLaw::Linear {
            k0: 1.0e7,
            two_gamma: 60.0,
        },
        tangential: TangentialLaw::History {
            ratio: 2.0 / 7.0,
            dt: 2.5e-5,
        },
        rolling: RollingLaw::None,
        cohesion: CohesionLaw::None,
    };
    let law = plain;
    bench_law(c, "spring-dashpot history", law, &mat, 0.0025);
    // the same with each pair's own normal coefficients (restitution per species and a
    // [[pairs]] override): what gathering them costs
    let mut per_pair = sd.clone();
    for (k, s) in per_pair.species.iter_mut().enumerate() {
        s.restitution = Some(0.9 - 0.1 * k as f64);
    }
    per_pair.pairs.push(tumbler::case::PairOverride {
        species: vec!["small".into(), "large".into()],
        mu: None,
        mu_roll: None,
        cohesion_energy: None,
        restitution: Some(0.7),
    });
    let law = ContactLaw {
        normal: NormalLaw::LinearPairs,
        ..plain
    };
    bench_law(
        c,
        "spring-dashpot history, per-pair normal",
        law,
        &Materials::new(&per_pair),
        0.0025,
    );
    // the same with the rolling spring and cohesion: what the sub-models cost
    let mut sticky = sd.clone();
    for s in sticky.species.iter_mut() {
        s.mu_roll = Some(0.3);
        s.cohesion_energy = Some(2.0e4);
    }
    let law = ContactLaw {
        rolling: RollingLaw::Sds {
            stiffness: 2.25,
            damping: 0.3,
            dt: 2.5e-5,
        },
        cohesion: CohesionLaw::Sjkr,
        ..plain
    };
    bench_law(
        c,
        "spring-dashpot history + rolling sds + sjkr",
        law,
        &Materials::new(&sticky),
        0.0025,
    );
    let rap = case("periodic.toml");
    let mat = Materials::new(&rap);
    bench_law(c, "rapaport", ContactLaw::new(&rap), &mat, 1.0);
}

criterion_group!(benches, kernels);
criterion_main!(benches);
