//! The batched, vectorised pair pass gives the same bits as the scalar reference laws, on
//! every instruction set this CPU has, for every contact law: forces, torques and
//! tangential histories, sliding and sticking contacts, contacts at rest, periodic images,
//! rough-wall particles and particles that are still growing (a pour); and every
//! composition with the rolling and cohesion sub-models.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumbler::engine::forces::{pair_forces_with, Isa};
use tumbler::engine::neighbor::{Grid, NeighborList};
use tumbler::particles::{ParticleState, Particles};
use tumbler::physics::cohesion::CohesionLaw;
use tumbler::physics::contact::HISTORY_MAX;
use tumbler::physics::normal::NormalLaw;
use tumbler::physics::rolling::RollingLaw;
use tumbler::physics::rough_wall::FIXED_SPECIES;
use tumbler::physics::tangential::TangentialLaw;
use tumbler::physics::{ContactLaw, Materials};

fn case(name: &str) -> tumbler::case::Case {
    let path = format!("{}/tests/cases/{name}", env!("CARGO_MANIFEST_DIR"));
    tumbler::case::parse_case(&std::fs::read_to_string(path).unwrap(), name).unwrap()
}

/// A dense random bed of `n` particles of diameter about `d` in a box of side `side`, a
/// tenth of them at rest, a few fixed to the wall.
fn bed(n: usize, d: f64, side: f64, mat: &Materials, seed: u64) -> Particles {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut p = Particles::default();
    for id in 0..n as u64 {
        let x = [
            rng.gen_range(0.0..side),
            rng.gen_range(0.0..side),
            rng.gen_range(0.0..side),
        ];
        let still = rng.gen_bool(0.1);
        let mut vec = |s: f64| {
            if still {
                [0.0; 3]
            } else {
                [
                    rng.gen_range(-s..s),
                    rng.gen_range(-s..s),
                    rng.gen_range(-s..s),
                ]
            }
        };
        let (v, w) = (vec(1.0), vec(20.0));
        let species = match id % 17 {
            16 => FIXED_SPECIES,
            k => (k % 2) as u8,
        };
        let dia = d * rng.gen_range(0.8..1.3);
        p.push_owned(&ParticleState::new(id, species, dia, x, v, w), mat);
    }
    p
}

/// Forces, torques and histories (flat, the law's words per pair) after a pair pass.
type Outcome = (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<f64>);

/// The pair pass of `law` on `p` with instruction set `isa`, the histories starting from
/// `hist`: forces, torques and histories after it.
#[allow(clippy::too_many_arguments)]
fn pass(
    isa: Isa,
    d: f64,
    p: &Particles,
    law: &ContactLaw,
    mat: &Materials,
    period: Option<f64>,
    scale: f64,
    hist: &[[f64; HISTORY_MAX]],
) -> Outcome {
    let mut p = p.clone();
    let reach = 1.2 * law.cutoff(1.3 * d, 1.3 * d);
    let grid = Grid::over([-2.0 * d; 3], [14.0 * d; 3], reach);
    let mut nl = NeighborList::default();
    nl.build(&p, &grid, 0.3 * reach, law);
    let w = nl.words;
    assert_eq!(w, law.history_words());
    assert!(nl.pairs.len() <= hist.len(), "{} pairs", nl.pairs.len());
    if w > 0 {
        for (k, h) in hist.iter().take(nl.pairs.len()).enumerate() {
            nl.hist.set(k, &h[..w]);
        }
    }
    for f in p.f.iter_mut().chain(p.t.iter_mut()) {
        *f = [0.0; 3];
    }
    pair_forces_with(isa, &mut p, &mut nl, law, mat, period, scale);
    // every pair's history, zeros where it holds none
    let mut words = Vec::new();
    for k in 0..nl.hist.len() {
        nl.hist.extend_into(k, &mut words);
    }
    (p.f, p.t, words)
}

fn bits(v: &[[f64; 3]]) -> Vec<[u64; 3]> {
    v.iter()
        .map(|x| [x[0].to_bits(), x[1].to_bits(), x[2].to_bits()])
        .collect()
}

fn flat_bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Every instruction set against the reference, on one law; returns the number of pairs
/// that touched, so a test can tell that it exercised something.
fn same_bits(law: ContactLaw, mat: &Materials, d: f64, scale: f64, period: Option<f64>) -> usize {
    let side = 12.0 * d;
    let p = bed(1500, d, side, mat, 5);
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    // histories: zero (of either sign: a pair apart keeps a -0.0 as the scalar law does),
    // small (sticking) and large (sliding)
    let hist: Vec<[f64; HISTORY_MAX]> = (0..40_000)
        .map(|i| {
            let mut h = [0.0; HISTORY_MAX];
            for w in h.chunks_exact_mut(3) {
                let v = match (i + rng.gen_range(0..2)) % 4 {
                    0 => [0.0; 3],
                    3 => [-0.0, 0.0, -0.0],
                    1 => [
                        rng.gen_range(-1e-3..1e-3) * d,
                        rng.gen_range(-1e-3..1e-3) * d,
                        rng.gen_range(-1e-3..1e-3) * d,
                    ],
                    _ => [rng.gen_range(-0.3..0.3) * d, 0.2 * d, -0.1 * d],
                };
                w.copy_from_slice(&v);
            }
            h
        })
        .collect();
    let period = period.map(|_| side);
    let reference = pass(Isa::Reference, d, &p, &law, mat, period, scale, &hist);
    let touching = reference.0.iter().filter(|f| **f != [0.0; 3]).count();
    for isa in [Isa::Base, Isa::Avx2, Isa::Avx512] {
        if isa > Isa::of_cpu() {
            eprintln!("{}: not on this CPU, skipped", isa.name());
            continue;
        }
        let got = pass(isa, d, &p, &law, mat, period, scale, &hist);
        assert_eq!(bits(&got.0), bits(&reference.0), "{}: forces", isa.name());
        assert_eq!(bits(&got.1), bits(&reference.1), "{}: torques", isa.name());
        // (a law without histories leaves them alone: only the reference clears them)
        if law.has_history() {
            assert_eq!(
                flat_bits(&got.2),
                flat_bits(&reference.2),
                "{}: histories",
                isa.name()
            );
        }
    }
    touching
}

fn spring_dashpot(normal: NormalLaw, tangential: TangentialLaw) -> ContactLaw {
    ContactLaw {
        normal,
        tangential,
        rolling: RollingLaw::None,
        cohesion: CohesionLaw::None,
    }
}

/// The materials of `sd_capped.toml` with rolling friction and cohesion, different for
/// the two species (so that mixed pairs mix them).
fn sticky_rolling_materials() -> Materials {
    let mut c = case("sd_capped.toml");
    for (k, s) in c.species.iter_mut().enumerate() {
        s.mu_roll = Some(0.2 + 0.1 * k as f64);
        s.mu_roll_wall = Some(0.4);
        s.cohesion_energy = Some(2.0e4 * (1 + k) as f64);
        s.cohesion_energy_wall = Some(1.0e4);
    }
    Materials::new(&c)
}

const SDS: RollingLaw = RollingLaw::Sds {
    stiffness: 2.25,
    damping: 0.3,
    dt: 2.5e-5,
};

const LINEAR: NormalLaw = NormalLaw::Linear {
    k0: 1.0e7,
    two_gamma: 60.0,
};
const HERTZ: NormalLaw = NormalLaw::Hertz {
    kh: 5.0e8,
    gamma_h: 2.0,
};
const HISTORY: TangentialLaw = TangentialLaw::History {
    ratio: 0.4,
    dt: 2.5e-5,
};

#[test]
fn spring_dashpot_laws_same_bits_scalar_and_vector() {
    let c = case("sd_capped.toml");
    let mat = Materials::new(&c);
    let d = 0.0025;
    for normal in [LINEAR, HERTZ] {
        for tangential in [
            HISTORY,
            TangentialLaw::Viscous { gamma_s: None },
            TangentialLaw::Viscous {
                gamma_s: Some(0.05),
            },
        ] {
            let law = spring_dashpot(normal, tangential);
            let n = same_bits(law, &mat, d, 1.0, None);
            assert!(n > 500, "{law:?}: only {n} particles touched");
            // periodic images, and particles still growing
            same_bits(law, &mat, d, 1.0, Some(0.0));
            same_bits(law, &mat, d, 0.93, None);
        }
    }
}

#[test]
fn history_law_slides_and_sticks_in_the_batches() {
    // the comparison above is only worth something if both branches of the Coulomb cut
    // and of the rotation of the history are taken
    let c = case("sd_capped.toml");
    let mat = Materials::new(&c);
    let law = spring_dashpot(LINEAR, HISTORY);
    let d = 0.0025;
    let side = 12.0 * d;
    let p = bed(1500, d, side, &mat, 5);
    let hist = vec![[0.0; HISTORY_MAX]; 40_000];
    let (_, _, h1) = pass(Isa::Reference, d, &p, &law, &mat, None, 1.0, &hist);
    let again = as_input(&h1, 3);
    let (_, _, h2) = pass(Isa::Reference, d, &p, &law, &mat, None, 1.0, &again);
    let cap = h2
        .chunks_exact(3)
        .zip(h1.chunks_exact(3))
        .filter(|(a, b)| *a != *b && **b != [0.0; 3])
        .count();
    assert!(cap > 100, "only {cap} histories changed in a second pass");
    let (_, _, h_auto) = pass(Isa::of_cpu(), d, &p, &law, &mat, None, 1.0, &again);
    assert_eq!(flat_bits(&h_auto), flat_bits(&h2));
}

/// Flat histories of `words` per pair as the input of another pass.
fn as_input(flat: &[f64], words: usize) -> Vec<[f64; HISTORY_MAX]> {
    let mut out = vec![[0.0; HISTORY_MAX]; 40_000];
    for (o, h) in out.iter_mut().zip(flat.chunks_exact(words)) {
        o[..words].copy_from_slice(h);
    }
    out
}

#[test]
fn rolling_and_cohesion_sub_models_same_bits_scalar_and_vector() {
    let mat = sticky_rolling_materials();
    let d = 0.0025;
    for normal in [LINEAR, HERTZ] {
        for tangential in [HISTORY, TangentialLaw::Viscous { gamma_s: None }] {
            for rolling in [
                RollingLaw::None,
                RollingLaw::Constant,
                RollingLaw::Viscous { eta: 1.0e-6 },
                SDS,
            ] {
                for cohesion in [CohesionLaw::None, CohesionLaw::Sjkr] {
                    let law = ContactLaw {
                        normal,
                        tangential,
                        rolling,
                        cohesion,
                    };
                    let n = same_bits(law, &mat, d, 1.0, None);
                    assert!(n > 500, "{law:?}: only {n} particles touched");
                    same_bits(law, &mat, d, 0.93, Some(0.0));
                }
            }
        }
    }
}

#[test]
fn rolling_spring_slips_and_holds_in_the_batches() {
    // both sides of the rolling spring's cut are taken: a stretched spring at a weak
    // contact is cut back to the limit, one at a strong contact holds its length (turned
    // into the tangent plane, plus one step of rolling)
    let mat = sticky_rolling_materials();
    let law = ContactLaw {
        normal: LINEAR,
        tangential: HISTORY,
        rolling: SDS,
        cohesion: CohesionLaw::Sjkr,
    };
    assert_eq!(law.history_words(), 6);
    let d = 0.0025;
    let p = bed(1500, d, 12.0 * d, &mat, 5);
    let stretched = [0.0, 0.0, 0.0, 0.03 * d, 0.02 * d, -0.01 * d];
    let hist = vec![stretched; 40_000];
    let (_, _, h) = pass(Isa::Reference, d, &p, &law, &mat, None, 1.0, &hist);
    let len = |w: &[f64]| (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let l0 = len(&stretched[3..]);
    let touching: Vec<f64> = h
        .chunks_exact(6)
        .filter(|w| w[3..] != [0.0; 3])
        .map(|w| len(&w[3..]) / l0)
        .collect();
    let cut = touching.iter().filter(|&&r| r < 0.9).count();
    let held = touching
        .iter()
        .filter(|&&r| (0.9..1.1).contains(&r))
        .count();
    assert!(
        cut > 50 && held > 50,
        "{cut} cut, {held} held of {}",
        touching.len()
    );
    let (_, _, h_auto) = pass(Isa::of_cpu(), d, &p, &law, &mat, None, 1.0, &hist);
    assert_eq!(flat_bits(&h_auto), flat_bits(&h));
}
#[test]
fn rapaport_law_same_bits_scalar_and_vector() {
    let c = case("periodic.toml");
    let mat = Materials::new(&c);
    let law = ContactLaw::new(&c);
    assert!(matches!(law.normal, NormalLaw::Rapaport { .. }));
    let n = same_bits(law, &mat, 1.0, 1.0, None);
    assert!(n > 500, "only {n} particles touched");
    same_bits(law, &mat, 1.0, 1.0, Some(0.0));
    same_bits(law, &mat, 1.0, 0.9, None);
}

/// The materials of `sd_capped.toml` with distinct normal coefficients per pair (and per
/// species against the walls, which a rough wall's particles stand for): restitution per
/// species and a `[[pairs]]` override for the linear law, Young's modulus and Poisson
/// ratio per species for Hertz; with rolling friction and cohesion as above.
fn per_pair_materials(hertz: bool) -> Materials {
    let mut c = case("sd_capped.toml");
    if hertz {
        c.model.normal = tumbler::case::Normal::Hertz;
        c.model.youngs_modulus = Some(1.0e7);
        c.model.poisson_ratio = Some(0.3);
        c.model.hertz_damping = Some(2.0);
    }
    for (k, s) in c.species.iter_mut().enumerate() {
        s.mu_roll = Some(0.2 + 0.1 * k as f64);
        s.cohesion_energy = Some(2.0e4 * (1 + k) as f64);
        if hertz {
            s.youngs_modulus = Some(1.0e7 * (1 + 3 * k) as f64);
            s.poisson_ratio = Some(0.3 - 0.05 * k as f64);
        } else {
            s.restitution = Some(0.9 - 0.2 * k as f64);
            s.restitution_wall = Some(0.6 + 0.1 * k as f64);
        }
    }
    if !hertz {
        c.pairs.push(tumbler::case::PairOverride {
            species: vec!["small".into(), "large".into()],
            mu: Some(0.3),
            mu_roll: None,
            cohesion_energy: None,
            restitution: Some(0.4),
        });
    }
    Materials::new(&c)
}

#[test]
fn per_pair_normal_coefficients_same_bits_scalar_and_vector() {
    let d = 0.0025;
    for (normal, hertz) in [
        (NormalLaw::LinearPairs, false),
        (NormalLaw::HertzPairs, true),
    ] {
        let mat = per_pair_materials(hertz);
        // the pairs do differ: like, mixed and wall (rough-wall particle) contacts
        let k = |a: u8, b: u8| mat.pair(a, b).normal_k;
        assert!(k(0, 0) != k(1, 1) && k(0, 1) != k(0, 0) && k(0, 1) != k(1, 1));
        assert!(k(0, FIXED_SPECIES) != k(1, FIXED_SPECIES));
        // (Hertz: a wall is of the species' material)
        assert!(hertz || k(0, FIXED_SPECIES) != k(0, 0));
        for tangential in [HISTORY, TangentialLaw::Viscous { gamma_s: None }] {
            for (rolling, cohesion) in [
                (RollingLaw::None, CohesionLaw::None),
                (SDS, CohesionLaw::Sjkr),
            ] {
                let law = ContactLaw {
                    normal,
                    tangential,
                    rolling,
                    cohesion,
                };
                let n = same_bits(law, &mat, d, 1.0, None);
                assert!(n > 500, "{law:?}: only {n} particles touched");
                same_bits(law, &mat, d, 0.93, Some(0.0));
            }
        }
        // and the per-pair law differs from the model's constants
        let c = case("sd_capped.toml");
        let uniform = ContactLaw::new(&c);
        let p = bed(1500, d, 12.0 * d, &mat, 5);
        let hist = vec![[0.0; HISTORY_MAX]; 40_000];
        if !hertz {
            let per_pair = spring_dashpot(NormalLaw::LinearPairs, HISTORY);
            let u = uniform;
            let a = pass(Isa::of_cpu(), d, &p, &per_pair, &mat, None, 1.0, &hist);
            let b = pass(
                Isa::of_cpu(),
                d,
                &p,
                &spring_dashpot(u.normal, HISTORY),
                &mat,
                None,
                1.0,
                &hist,
            );
            assert_ne!(bits(&a.0), bits(&b.0));
        }
    }
}
