//! The batched, vectorised walls' pass gives the same bits as the scalar wall law, one
//! particle at a time, on every instruction set this CPU has: forces, torques and wall
//! histories, for every composition of the contact law, on every vessel (a capped cylinder,
//! lifters, a sphere, a cone), with particles still growing and histories sliding,
//! sticking, zero and `-0.0`.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumbler::engine::forces::Isa;
use tumbler::engine::wall_pass::{wall_and_body_forces_with, WallForces, WallScratch};
use tumbler::particles::{ParticleState, Particles};
use tumbler::physics::cohesion::CohesionLaw;
use tumbler::physics::materials::WALLS;
use tumbler::physics::normal::NormalLaw;
use tumbler::physics::rolling::RollingLaw;
use tumbler::physics::tangential::TangentialLaw;
use tumbler::physics::{ContactLaw, DrumWalls, Materials, V3};

mod common;

fn case(name: &str) -> tumbler::case::Case {
    common::case_with(name, &[])
}

/// A case's materials with rolling friction and cohesion, against each other and the walls,
/// different for each species.
fn sticky(c: &mut tumbler::case::Case) {
    for (k, s) in c.species.iter_mut().enumerate() {
        s.mu_roll = Some(0.2 + 0.1 * k as f64);
        s.mu_roll_wall = Some(0.4 - 0.1 * k as f64);
        s.cohesion_energy = Some(2.0e4 * (1 + k) as f64);
        s.cohesion_energy_wall = Some(1.0e4 * (1 + k) as f64);
    }
}

/// `n` particles of about the species' diameters within reach of a wall of `walls` and
/// inside it by at least a third of their diameter (so that some overlap a wall and some do
/// not), a tenth at rest; every wall slot of `words` history words random: zero (of
/// either sign), small or large.
fn bed(c: &tumbler::case::Case, walls: &DrumWalls, mat: &Materials, words: usize) -> Particles {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut p = Particles::new(words);
    let (r, h) = (walls.radius, walls.half_length);
    let mut id = 0u64;
    while p.n_owned < 1500 {
        let species = (id % c.species.len() as u64) as u8;
        let d = c.species[species as usize].diameter * rng.gen_range(0.8..1.2);
        let x = [
            rng.gen_range(-r..r),
            rng.gen_range(-r..r),
            rng.gen_range(-h..h),
        ];
        if !walls.near(x, 0.7 * d) || !walls.inside(x, 0.3 * d) {
            continue;
        }
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
        let (v, w) = (vec(0.5), vec(50.0));
        let mut s = ParticleState::new(id, species, d, x, v, w);
        for slot in s.wall_hist.iter_mut() {
            for word in slot[..words].chunks_exact_mut(3) {
                let v = match rng.gen_range(0..4) {
                    0 => [0.0; 3],
                    1 => [-0.0, 0.0, -0.0],
                    2 => [
                        rng.gen_range(-1e-4..1e-4) * d,
                        rng.gen_range(-1e-4..1e-4) * d,
                        rng.gen_range(-1e-4..1e-4) * d,
                    ],
                    _ => [rng.gen_range(-0.3..0.3) * d, 0.2 * d, -0.1 * d],
                };
                word.copy_from_slice(&v);
            }
        }
        p.push_owned(&s, mat);
        id += 1;
    }
    p
}

fn bits(v: &[[f64; 3]]) -> Vec<[u64; 3]> {
    v.iter()
        .map(|x| [x[0].to_bits(), x[1].to_bits(), x[2].to_bits()])
        .collect()
}

/// Forces, torques and every particle's wall histories (flat) after a walls' pass.
type Outcome = (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<u64>);

fn pass(isa: Isa, p: &Particles, env: &WallForces) -> Outcome {
    let mut p = p.clone();
    let near: Vec<u32> = (0..p.n_owned as u32).collect();
    let mut scratch = WallScratch::default();
    // twice: the second pass starts from the first's histories and blocks
    for _ in 0..2 {
        wall_and_body_forces_with(isa, &mut p, &near, &mut scratch, env);
    }
    let mut words = Vec::new();
    for i in 0..p.n_owned {
        p.wall_hist.extend_into(i, &mut words);
    }
    let words = words.iter().map(|x| x.to_bits()).collect();
    (p.f, p.t, words)
}

/// Every instruction set against the reference for `law` on the drum of `c`, at diameter
/// scale `scale`; returns how many particles touch each wall slot.
fn same_bits(c: &tumbler::case::Case, law: ContactLaw, scale: f64) -> [usize; WALLS] {
    let mat = Materials::new(c);
    let mut walls = DrumWalls::of(&c.drum);
    walls.turn_to(0.3);
    let p = bed(c, &walls, &mat, law.history_words());
    let env = WallForces {
        walls: &walls,
        law: &law,
        mat: &mat,
        gravity: 9.8,
        scale,
    };
    let reference = pass(Isa::Reference, &p, &env);
    for isa in [Isa::Base, Isa::Avx2, Isa::Avx512] {
        if isa > Isa::of_cpu() {
            eprintln!("{}: not on this CPU, skipped", isa.name());
            continue;
        }
        let got = pass(isa, &p, &env);
        let what = format!("{} on {}, {law:?}", isa.name(), c.title);
        assert_eq!(bits(&got.0), bits(&reference.0), "{what}: forces");
        assert_eq!(bits(&got.1), bits(&reference.1), "{what}: torques");
        assert_eq!(got.2, reference.2, "{what}: wall histories");
    }
    let mut touching = [0; WALLS];
    for i in 0..p.n_owned {
        let d = p.diameter[i] * scale;
        let d_iw = law.normal.wall_contact(d);
        let rc = law.normal.range(d_iw);
        let found = walls.contacts(V3::from(p.x[i]), law.wall_reach(d));
        for (k, t) in found.iter().enumerate() {
            if t.is_some_and(|t| t.r.norm() < rc) {
                touching[k] += 1;
            }
        }
    }
    touching
}

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
const SDS: RollingLaw = RollingLaw::Sds {
    stiffness: 2.25,
    damping: 0.3,
    dt: 2.5e-5,
};

#[test]
fn every_law_on_every_vessel_same_bits_scalar_and_vector() {
    // (the lifter drum has frictionless caps, the sphere no caps at all)
    let slots = [
        ("sd_capped.toml", [true, true, true, false]),
        ("lifters.toml", [true, true, true, true]),
        ("sphere.toml", [true, false, false, false]),
        ("cone.toml", [true, true, true, false]),
    ];
    for (name, has) in slots {
        let mut c = case(name);
        sticky(&mut c);
        for normal in [LINEAR, HERTZ] {
            for tangential in [
                HISTORY,
                TangentialLaw::Viscous { gamma_s: None },
                TangentialLaw::Viscous {
                    gamma_s: Some(0.05),
                },
            ] {
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
                        let touching = same_bits(&c, law, 1.0);
                        for (k, (&n, &has)) in touching.iter().zip(&has).enumerate() {
                            assert!((n > 20) == has, "{name}: {n} particles touch wall slot {k}");
                        }
                        same_bits(&c, law, 0.93);
                    }
                }
            }
        }
    }
}

#[test]
fn per_pair_normal_coefficients_and_rapaport_same_bits_scalar_and_vector() {
    // restitution against the walls per species (the linear law's own coefficients per
    // wall), Young's modulus per species (Hertz: a wall is of the species' material)
    let mut c = case("lifters.toml");
    sticky(&mut c);
    c.species[0].restitution_wall = Some(0.6);
    for tangential in [HISTORY, TangentialLaw::Viscous { gamma_s: None }] {
        for (rolling, cohesion) in [
            (RollingLaw::None, CohesionLaw::None),
            (SDS, CohesionLaw::Sjkr),
        ] {
            let law = ContactLaw {
                normal: NormalLaw::LinearPairs,
                tangential,
                rolling,
                cohesion,
            };
            assert!(same_bits(&c, law, 1.0)[0] > 20);
        }
    }
    let mut h = case("sd_capped.toml");
    sticky(&mut h);
    h.model.normal = tumbler::case::Normal::Hertz;
    h.model.youngs_modulus = Some(1.0e7);
    h.model.poisson_ratio = Some(0.3);
    h.model.hertz_damping = Some(2.0);
    for (k, s) in h.species.iter_mut().enumerate() {
        s.youngs_modulus = Some(1.0e7 * (1 + 3 * k) as f64);
    }
    let law = ContactLaw {
        normal: NormalLaw::HertzPairs,
        tangential: HISTORY,
        rolling: SDS,
        cohesion: CohesionLaw::Sjkr,
    };
    assert!(same_bits(&h, law, 1.0)[1] > 20);
    // Rapaport's walls (the paper's divisions and lever), in reduced units
    let r = case("capped.toml");
    let law = ContactLaw::new(&r);
    assert!(matches!(law.normal, NormalLaw::Rapaport { .. }));
    let touching = same_bits(&r, law, 1.0);
    assert!(touching[0] > 20 && touching[1] > 20, "{touching:?}");
    same_bits(&r, law, 0.9);
}

#[test]
fn a_history_law_slides_and_sticks_on_the_walls() {
    // the comparison is only worth something if the walls' histories take both branches of
    // the Coulomb cut: some come out shorter than they went in, some longer
    let mut c = case("sd_capped.toml");
    sticky(&mut c);
    let law = ContactLaw {
        normal: LINEAR,
        tangential: HISTORY,
        rolling: RollingLaw::None,
        cohesion: CohesionLaw::None,
    };
    let mat = Materials::new(&c);
    let walls = DrumWalls::of(&c.drum);
    let p = bed(&c, &walls, &mat, 3);
    let env = WallForces {
        walls: &walls,
        law: &law,
        mat: &mat,
        gravity: 9.8,
        scale: 1.0,
    };
    let mut after = p.clone();
    let near: Vec<u32> = (0..p.n_owned as u32).collect();
    wall_and_body_forces_with(
        Isa::of_cpu(),
        &mut after,
        &near,
        &mut WallScratch::default(),
        &env,
    );
    let len = |h: &[f64]| (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
    let (mut cut, mut grown) = (0, 0);
    for i in 0..p.n_owned {
        let (Some(a), Some(b)) = (p.wall_hist.get(i), after.wall_hist.get(i)) else {
            continue;
        };
        for k in 0..WALLS {
            let (la, lb) = (len(&a[3 * k..]), len(&b[3 * k..]));
            if la > 0.0 && lb > 0.0 {
                cut += (lb < 0.9 * la) as usize;
                grown += (lb > la) as usize;
            }
        }
    }
    assert!(cut > 20 && grown > 20, "{cut} cut back, {grown} grown");
}
