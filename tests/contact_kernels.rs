//! The Rapaport contact kernels against hand-computed values (section III).

use tumbler::physics::rapaport::{self, Friction, CUTOFF_FACTOR, KAPPA, V3};

const FR: Friction = Friction::sliding(10.0, 0.5);

#[test]
fn repulsion_matches_eq1_by_hand() {
    // r = d: 48/d (1 - 1/2) = 24/d
    assert_eq!(rapaport::repulsion(1.0, 1.0), 24.0);
    assert_eq!(rapaport::repulsion(2.0, 2.0), 12.0);
    // r = 0.95, d = 1: 48/0.95 (0.95^-12 - 0.5 * 0.95^-6)
    let r: f64 = 0.95;
    let expect = 48.0 / r * (r.powi(-12) - 0.5 * r.powi(-6));
    assert!((rapaport::repulsion(r, 1.0) - expect).abs() < 1e-12 * expect);
}

#[test]
fn repulsion_is_continuous_at_the_cutoff() {
    for d in [0.8, 1.0, 1.15, 1.3] {
        let rc = CUTOFF_FACTOR * d;
        // at the cutoff the bracket vanishes: (d/r)^6 = 1/2
        let just_inside = rapaport::repulsion(rc * (1.0 - 1e-9), d);
        assert!((0.0..1e-6).contains(&just_inside), "{just_inside}");
        assert_eq!(rapaport::repulsion(rc, d), 0.0);
        assert_eq!(rapaport::repulsion(rc * 1.01, d), 0.0);
        // and it is repulsive everywhere inside
        for k in 1..100 {
            let r = rc * k as f64 / 100.0;
            assert!(rapaport::repulsion(r, d) > 0.0);
        }
    }
}

#[test]
fn pair_force_is_equal_and_opposite() {
    let (xa, xb) = (V3::new(0.1, 0.2, 0.3), V3::new(0.5, 0.9, 0.1));
    let (va, vb) = (V3::new(1.0, -2.0, 0.5), V3::new(-0.3, 0.4, 0.2));
    let (wa, wb) = (V3::new(0.3, 0.1, -2.0), V3::new(1.5, -0.7, 0.2));
    let (da, db) = (1.0, 0.9);
    let ab = rapaport::pair(xa - xb, va, vb, wa, wb, da, db, 5.0, FR).expect("in contact");
    let ba = rapaport::pair(xb - xa, vb, va, wb, wa, db, da, 5.0, FR).expect("in contact");
    for k in 0..3 {
        assert!((ab.force[k] + ba.force[k]).abs() < 1e-12, "{ab:?} {ba:?}");
        // n flips and f_s flips: n x f_s is the same seen from either side
        assert!((ab.n_cross_fs[k] - ba.n_cross_fs[k]).abs() < 1e-12);
    }
}

#[test]
fn pair_force_by_hand_with_damping_and_capped_friction() {
    // a along +x from b, overlapping; approaching along x, sliding along y.
    let r = V3::new(0.9, 0.0, 0.0);
    let va = V3::new(-1.0, 2.0, 0.0);
    let vb = V3::zeros();
    let w = V3::zeros();
    let c = rapaport::pair(r, va, vb, w, w, 1.0, 1.0, 5.0, FR).unwrap();
    let fv = rapaport::repulsion(0.9, 1.0);
    let (gamma_n, v_n) = (5.0, -1.0); // approaching
    let f_n = fv - gamma_n * v_n; // eq. 2 adds +5
    assert!((c.force.x - f_n).abs() < 1e-12);
    // sliding speed 2 along +y: gamma_s*2 = 20 > mu*f_n? f_n is large, so viscous 20 wins
    let f_s = -(10.0f64 * 2.0).min(0.5 * f_n);
    assert!((c.force.y - f_s).abs() < 1e-12, "{} {}", c.force.y, f_s);
    assert_eq!(c.force.z, 0.0);
    // n x f_s = x^ x (f_s y^) = f_s z^
    assert!((c.n_cross_fs.z - f_s).abs() < 1e-12);

    // With a weak normal force, the Coulomb cap mu |f_n| applies instead.
    let r = V3::new(CUTOFF_FACTOR * 0.999, 0.0, 0.0);
    let c = rapaport::pair(r, V3::new(0.0, 2.0, 0.0), vb, w, w, 1.0, 1.0, 0.0, FR).unwrap();
    let f_n = rapaport::repulsion(r.x, 1.0);
    assert!((c.force.y + 0.5 * f_n).abs() < 1e-12);
}

#[test]
fn spins_enter_the_sliding_velocity_as_eq3() {
    // Two equal touching spheres spinning in the same sense about z: surfaces at the contact
    // move in opposite directions, so the sliding velocity is -(w d_i + w d_j)/(d_i+d_j) x r.
    let r = V3::new(1.0, 0.0, 0.0);
    let w = V3::new(0.0, 0.0, 1.0);
    let fr = Friction::sliding(1.0, 100.0);
    let c = rapaport::pair(r, V3::zeros(), V3::zeros(), w, w, 1.0, 1.0, 0.0, fr).unwrap();
    // v_s = -(w x r) = -(z^ x x^) = -y^, so f_s = -gamma_s v_s = +y^
    assert!((c.force.y - 1.0).abs() < 1e-12, "{:?}", c.force);
}

#[test]
fn torque_rule_of_section_iii() {
    // m_i d_i alpha_i = -n x f_s / kappa for both particles, with m = d^3 and I = m d^2 / 10.
    use tumbler::engine::forces::pair_forces;
    use tumbler::engine::neighbor::{Grid, NeighborList};
    use tumbler::particles::{ParticleState, Particles};
    use tumbler::physics::Materials;

    let case = tumbler::case::parse_case(&common_case(), "test").unwrap();
    let mat = Materials::new(&case);
    let mut p = Particles::default();
    let a = ParticleState::new(0, 0, 1.0, [0.0; 3], [0.0, 1.0, 0.3], [0.0; 3]);
    let b = ParticleState::new(
        1,
        1,
        1.2,
        [1.05, 0.0, 0.0],
        [0.0, -0.5, 0.0],
        [0.2, 0.0, 0.0],
    );
    p.push_owned(&a, &mat);
    p.push_owned(&b, &mat);
    let mut nl = NeighborList::default();
    let law = tumbler::physics::ContactLaw::new(&case);
    nl.build(&p, &Grid::new(5.0, -5.0, 5.0, 2.0), 0.3, &law);
    assert_eq!(nl.pairs.len(), 1);
    pair_forces(&mut p, &mut nl, &law, &mat, None, 1.0);
    let c = rapaport::pair(
        V3::from(a.x) - V3::from(b.x),
        V3::from(a.v),
        V3::from(b.v),
        V3::from(a.w),
        V3::from(b.w),
        1.0,
        1.2,
        case.model.gamma_n.unwrap(),
        mat.pair(0, 1),
    )
    .unwrap();
    assert!(c.n_cross_fs.norm() > 0.0);
    for (i, d) in [(0usize, 1.0f64), (1, 1.2)] {
        let m = 1.0 / p.inv_mass[i];
        assert!((m - d * d * d).abs() < 1e-12, "m = d^3");
        let alpha = V3::from(p.t[i]) * p.inv_inertia[i];
        let lhs = alpha * (m * d);
        let rhs = -c.n_cross_fs / KAPPA;
        assert!((lhs - rhs).norm() < 1e-9 * rhs.norm(), "{lhs:?} {rhs:?}");
    }
    // and the forces are equal and opposite
    for k in 0..3 {
        assert_eq!(p.f[0][k], -p.f[1][k]);
    }
}

fn common_case() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/cases/periodic.toml"
    ))
    .unwrap()
}

/// Rapaport's law is a composition of the contact law's slots (its repulsion and dashpot
/// as the normal slot, viscous sliding with each pair's `gamma_s` as the tangential one):
/// the composed law gives the same bits as the paper's formulas written out in
/// `rapaport::pair` and `rapaport::wall`, touching or not, for pairs and walls.
#[test]
fn the_composed_rapaport_law_is_the_papers_formulas_bit_for_bit() {
    use rand::{Rng, SeedableRng};
    use tumbler::physics::normal::NormalLaw;
    use tumbler::physics::tangential::TangentialLaw;
    use tumbler::physics::{Body, Contact, ContactLaw};
    let (gamma_n, wall_diameter) = (5.0, 1.3);
    let law = ContactLaw {
        normal: NormalLaw::Rapaport {
            gamma_n,
            wall_diameter,
        },
        tangential: TangentialLaw::ViscousPairs,
        rolling: Default::default(),
        cohesion: tumbler::physics::cohesion::CohesionLaw::None,
    };
    assert_eq!(law.history_words(), 0);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2002);
    let mut v3 = |s: f64| {
        V3::new(
            rng.gen_range(-s..s),
            rng.gen_range(-s..s),
            rng.gen_range(-s..s),
        )
    };
    let bits = |c: Option<Contact>| {
        c.map(|c| {
            [c.force, c.n_cross_fs, c.torque_roll]
                .map(|v| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()])
        })
    };
    let (mut touching, mut apart) = (0, 0);
    for k in 0..20_000 {
        let (da, db) = (
            0.8 + 0.2 * (k % 5) as f64 / 4.0,
            0.8 + 0.05 * (k % 7) as f64,
        );
        let fr = Friction::sliding(0.5 + (k % 3) as f64 * 4.0, 0.1 * (k % 6) as f64);
        let r = v3(1.0);
        let a = Body {
            v: v3(2.0),
            w: v3(3.0),
            d: da,
            inv_mass: 1.0 / (da * da * da),
        };
        let b = Body {
            v: v3(2.0),
            w: v3(3.0),
            d: db,
            inv_mass: 1.0 / (db * db * db),
        };
        let paper = rapaport::pair(r, a.v, b.v, a.w, b.w, da, db, gamma_n, fr);
        if paper.is_some() {
            touching += 1;
        } else {
            apart += 1;
        }
        assert_eq!(
            bits(law.pair(r, &a, &b, fr, &mut [])),
            bits(paper),
            "pair {k}"
        );
        let v_wall = v3(1.0);
        let paper = rapaport::wall(r, a.v, a.w, v_wall, 0.5 * (da + wall_diameter), gamma_n, fr);
        assert_eq!(
            bits(law.wall(r, &a, v_wall, V3::zeros(), fr, &mut [])),
            bits(paper),
            "wall {k}"
        );
    }
    assert!(
        touching > 5000 && apart > 5000,
        "{touching} touching, {apart} apart"
    );
    // its ranges are the paper's cutoffs
    assert_eq!(law.cutoff(1.0, 0.8), rapaport::cutoff(0.9));
    assert_eq!(
        law.wall_reach(0.8),
        rapaport::cutoff(0.5 * (0.8 + wall_diameter))
    );
}
