//! Cohesion raises a drum's dynamic angle of repose, monotonically with the cohesion energy
//! density: the small capped drum of `cohesive.toml` (the drum, beads and fill of
//! `sd_capped.toml`, slumping at 6 rad/s, with the Hertz normal force) turned two rotations
//! with simplified-JKR cohesion between particles at `k_c` = 0, 6e4 and 1e5 J/m^3.
//!
//! Why Hertz: with the linear spring the SJKR attraction `2 pi R_eff k_c delta` is linear in
//! the overlap too, so it only softens the spring and gives no finite pull-off force. With
//! Hertz the net repulsion of a pair at overlap `delta` is
//! `F(delta) = K delta^1.5 - C delta`, `K = k_h sqrt(R_eff)`, `k_h = 2 Y / (3 (1 - nu^2))`,
//! and (contact circle `a^2 = 2 R_eff delta` for small overlaps) `C = 2 pi k_c R_eff`. It is
//! most attractive at `delta* = (2C / 3K)^2`, where the pull-off force is
//! `F_po = 4 C^3 / (27 K^2) = 32 pi^3 k_c^3 R_eff^2 / (27 k_h^2)`, and rests at
//! `delta_0 = (C / K)^2`. Here `Y` = 5e6 Pa, `nu` = 0.3: `k_h` = 3.663e6 Pa. The Bond number
//! of equal beads of diameter `d` (`R_eff = d/4`), `Bo = F_po / (m g)` with
//! `m = 2500 pi d^3 / 6`, goes as `k_c^3 / d`:
//!
//! | `k_c` (J/m^3) | `Bo`, 2 mm | `Bo`, 3 mm | `delta_0 / d` |
//! |---|---|---|---|
//! | 0     | 0    | 0    | 0       |
//! | 6e4   | 1.44 | 0.96 | 0.27 %  |
//! | 1e5   | 6.7  | 4.5  | 0.74 %  |
//!
//! (2 mm: `F_po` = 1.48e-4 and 6.85e-4 N against `m g` = 1.03e-4 N; 3 mm: 3.33e-4 and
//! 1.54e-3 N against 3.46e-4 N.) The walls and caps do not attract: with the wall at the
//! same `k_c` (whose `R_eff` is twice a pair's, so four times the pull-off), clumps ride on
//! the wall over the top and the surface fit loses its meaning.
//!
//! The time step 2e-5 s is about 9 steps of the shortest Hertz contact at the check's
//! characteristic impact speed (1.1 m/s, smallest beads); `hertz_damping` 1.0 gives a
//! restitution of 0.88-0.93 between 2 mm beads at 0.05-0.3 m/s.
//!
//! Measured (mean of `/slices/angle_drum` over the windows from 0.3 rotations on, seeds 11,
//! 12, 13): 29.5, 28.8, 29.2 degrees without cohesion; 32.8, 33.1, 32.9 at 6e4; 37.3, 36.7,
//! 37.5 at 1e5. So the run-to-run scatter of the mean is 0.2-0.4 degrees; the windows
//! themselves scatter by 3, 4 and 12 degrees (s.d.), and means of 0.2-rotation blocks by
//! 1-2, 1.5 and 3-4 degrees. The cohesive beds are intermittent: at 1e5 the bed turns with
//! the drum to 50-55 degrees and then fails in clumps, down to about 20 (the bed's mean
//! angular velocity swings between -4 and +5 rad/s); at 1.2e5 (`Bo` 8-12) the bed moves
//! as one lump that slides and rocks on the non-attracting wall and the mean angle falls
//! back to 33-35: a drum twelve bead diameters across holds no flowing bed that cohesive.
//! The first 0.3 rotation (the rise from the flat poured bed and its first, deepest
//! avalanche) is left out.

mod common;

use common::{case_with, run_case, tmpdir};
use std::f64::consts::PI;
use tumbler::physics::rapaport::{Friction, V3};
use tumbler::physics::{Body, ContactLaw};

/// Mean whole-drum angle of repose over the windows that start from 0.3 rotations on.
fn mean_angle(path: &std::path::Path) -> f64 {
    let f = hdf5::File::open(path).unwrap();
    let a: Vec<f32> = f.dataset("slices/angle_drum").unwrap().read_raw().unwrap();
    let start: Vec<f64> = f
        .dataset("slices/rotations_start")
        .unwrap()
        .read_raw()
        .unwrap();
    assert_eq!(a.len(), start.len());
    let late: Vec<f64> = a
        .iter()
        .zip(&start)
        .filter(|(x, &s)| s >= 0.3 - 1e-9 && x.is_finite())
        .map(|(&x, _)| x as f64)
        .collect();
    assert!(late.len() >= 80, "{} windows", late.len());
    late.iter().sum::<f64>() / late.len() as f64
}

#[test]
fn cohesion_raises_the_angle_of_repose_monotonically() {
    let dir = tmpdir();
    let mut angles = Vec::new();
    for k_c in [0.0, 6.0e4, 1.0e5] {
        let out = dir.path().join(format!("kc{k_c}.h5"));
        let k0 = format!("species.0.cohesion_energy={k_c}");
        let k1 = format!("species.1.cohesion_energy={k_c}");
        run_case(2, "cohesive.toml", &out, &[k0.as_str(), k1.as_str()]);
        angles.push(mean_angle(&out));
    }
    // measured: about 29, 33 and 37 degrees, the means' run-to-run scatter 0.2-0.4 degrees
    assert!(
        (25.0..35.0).contains(&angles[0]),
        "without cohesion the angle of repose is {}",
        angles[0]
    );
    assert!(
        angles[1] > angles[0] + 2.0 && angles[2] > angles[1] + 2.0,
        "angles of repose {angles:?} for k_c 0, 6e4, 1e5 J/m^3"
    );
}

/// The pull-off force of a Hertz + SJKR pair (the most attractive net normal force) is
/// `4 C^3 / (27 K^2)`, as the Bond numbers above assume (to 1 %: the exact contact circle is
/// a little smaller than `2 R_eff delta`).
#[test]
fn hertz_sjkr_pull_off_force_is_as_the_bond_arithmetic_says() {
    let case = case_with("cohesive.toml", &[]);
    let law = ContactLaw::new(&case);
    let (y, nu) = (case.model.youngs_modulus.unwrap(), 0.3);
    assert_eq!(case.model.poisson_ratio, Some(nu));
    let kh = 2.0 * y / (3.0 * (1.0 - nu * nu));
    for (k_c, d) in [(6.0e4, 0.002), (1.0e5, 0.002), (1.0e5, 0.003)] {
        let m = 2500.0 * PI / 6.0 * d * d * d;
        let body = Body {
            v: V3::zeros(),
            w: V3::zeros(),
            d,
            inv_mass: 1.0 / m,
        };
        let fr = Friction {
            gamma_s: 0.0,
            mu: 0.5,
            mu_roll: 0.0,
            cohesion: k_c,
            normal_k: kh,
            normal_c: case.model.hertz_damping.unwrap(),
        };
        let r_eff = 0.25 * d;
        let (c, k) = (2.0 * PI * k_c * r_eff, kh * r_eff.sqrt());
        let pull_off = 4.0 * c * c * c / (27.0 * k * k);
        let delta_star = (2.0 * c / (3.0 * k)).powi(2);
        // the net force along n from just touching to four times delta*
        let mut most = f64::INFINITY;
        let mut at = 0.0;
        for i in 1..=4000 {
            let delta = delta_star * i as f64 / 1000.0;
            let mut hist = [0.0; 6];
            let r = V3::new(d - delta, 0.0, 0.0);
            let f = law.pair(r, &body, &body, fr, &mut hist).unwrap().force.x;
            if f < most {
                (most, at) = (f, delta);
            }
        }
        assert!(
            (-most - pull_off).abs() < 1e-2 * pull_off,
            "k_c {k_c}, d {d}: most attractive {most} N at {at}, theory {pull_off} N at {delta_star}"
        );
        assert!((at - delta_star).abs() < 0.05 * delta_star);
        let bond = pull_off / (m * case.model.gravity);
        println!("k_c {k_c} d {d}: F_po {pull_off:.4e} N, Bo {bond:.2}");
    }
}
