//! The wall-geometry layer (`physics/walls/`): lifters and a conical drum. Closest points,
//! distances and wall velocities of the new surfaces against hand values; a sphere resting
//! on a lifter feels its weight; a lifter drum showers (more particles airborne than in the
//! same drum without lifters); a bed in a cone stays inside and keeps every particle; bad
//! lifter and cone keys are refused with the key and the reason.

mod common;

use common::{case_path, case_with, tumbler};
use tumbler::case::{apply_overrides, parse_case, Drum};
use tumbler::comm::SerialComm;
use tumbler::engine::{thermo, Sim};
use tumbler::init::{initial_particles, pour, Share};
use tumbler::particles::ParticleState;
use tumbler::physics::walls::{wall_velocity, Cone, DrumWalls, Lifters};
use tumbler::physics::V3;

fn drum(text: &str) -> Drum {
    toml::from_str(&format!("omega = 2.0\n{text}")).unwrap()
}

/// R = 1, four lifters 0.2 high and 0.02 thick along the whole (capped) drum, lifter 0 along
/// +x at time zero.
fn lifter_walls() -> DrumWalls {
    DrumWalls::of(&drum(
        "diameter = 2.0\nlength = 4.0\nends = \"capped\"\n[lifters]\ncount = 4\nheight = 0.2\nthickness = 0.02",
    ))
}

fn close(a: V3, b: V3, what: &str) {
    assert!((a - b).norm() < 1e-12, "{what}: {a:?} vs {b:?}");
}

#[test]
fn lifter_face_tip_and_edge_give_the_closest_point() {
    let w = lifter_walls();
    let l = w.lifters.as_ref().unwrap();
    let half = 0.01;
    // face: above lifter 0 (the plate y = 0, 0.81 <= x <= 1), 0.05 over its face
    let x = V3::new(0.9, half + 0.05, 0.3);
    let t = l.contact(x, 0.1).expect("within reach of the face");
    close(t.r, V3::new(0.0, 0.05, 0.0), "face: r");
    close(t.at, V3::new(0.9, half, 0.3), "face: wall point");
    close(
        wall_velocity(t.at, w.omega),
        V3::new(-2.0 * half, 2.0 * 0.9, 0.0),
        "face: v_wall = omega z x x_wall",
    );
    // out of reach of the face: no contact
    assert!(l.contact(V3::new(0.9, half + 0.2, 0.3), 0.1).is_none());
    // tip: on the mid-plane, 0.03 inside the tip (the innermost point is at R - h = 0.8)
    let t = l.contact(V3::new(0.77, 0.0, -1.0), 0.1).unwrap();
    close(t.r, V3::new(-0.03, 0.0, 0.0), "tip: r");
    close(t.at, V3::new(0.8, 0.0, -1.0), "tip: wall point");
    // rounded edge of the tip: the closest point of the half-cylinder of radius t/2 about
    // the tip's mid-line at x = 0.81, in the direction of the centre
    let x = V3::new(0.81 - 0.03, 0.04, 0.0);
    let t = l.contact(x, 0.1).unwrap();
    let dir = V3::new(-0.03, 0.04, 0.0) / 0.05;
    close(t.r, dir * (0.05 - half), "edge: r");
    close(
        t.at,
        V3::new(0.81, 0.0, 0.0) + dir * half,
        "edge: wall point",
    );
    // lifter 1 (along +y) from its side: distance measured across the plate x = 0
    let t = l.contact(V3::new(-0.04, 0.95, 0.0), 0.1).unwrap();
    close(t.r, V3::new(-0.03, 0.0, 0.0), "lifter 1: r");
    // turned by an eighth of a turn, lifter 0 points along the diagonal
    let mut turned = w.clone();
    turned.turn_to(std::f64::consts::FRAC_PI_4);
    let l = turned.lifters.as_ref().unwrap();
    assert!(l.contact(V3::new(0.9, half + 0.05, 0.3), 0.1).is_none());
    let c = std::f64::consts::FRAC_1_SQRT_2;
    let (along, across) = (V3::new(c, c, 0.0), V3::new(-c, c, 0.0));
    let t = l
        .contact(along * 0.9 + across * (half + 0.05), 0.1)
        .unwrap();
    close(t.r, across * 0.05, "turned lifter: r");
}

#[test]
fn lifter_span_ends_are_rounded() {
    let w = DrumWalls::of(&drum(
        "diameter = 2.0\nlength = 4.0\nends = \"capped\"\n[lifters]\ncount = 2\nheight = 0.2\nthickness = 0.02\nspan = [-1.0, 1.0]",
    ));
    let l = w.lifters.as_ref().unwrap();
    // beyond the span's end at z = 1, on the plate's mid-plane
    let t = l.contact(V3::new(0.9, 0.0, 1.05), 0.1).unwrap();
    close(t.r, V3::new(0.0, 0.0, 0.04), "span end: r");
    // the corner of the tip and the span end: the closest point of the rectangle is the corner
    let x = V3::new(0.81 - 0.03, 0.0, 1.04);
    let t = l.contact(x, 0.1).unwrap();
    close(
        t.r,
        V3::new(-0.03, 0.0, 0.04) * (1.0 - 0.01 / 0.05),
        "corner: r",
    );
    assert!(l.contact(V3::new(0.9, 0.0, 1.2), 0.1).is_none());
}

#[test]
fn the_drum_asks_its_lifters_for_inside_near_and_volume() {
    let w = lifter_walls();
    assert!(w.inside([0.5, 0.0, 0.0], 0.05));
    assert!(!w.inside([0.9, 0.0, 0.0], 0.0), "inside lifter 0");
    assert!(!w.inside([0.9, 0.03, 0.0], 0.05), "overlapping lifter 0");
    assert!(w.inside([0.9, 0.1, 0.0], 0.05));
    // near: the annulus the lifters sweep (R - h - reach), at any angle
    assert!(w.near([0.0, -0.75, 0.0], 0.06));
    assert!(!w.near([0.0, -0.7, 0.0], 0.06));
    let plain = std::f64::consts::PI * 4.0;
    let lifters = 4.0 * 4.0 * ((1.0 - 0.81) * 0.02 + std::f64::consts::PI * 0.02 * 0.02 / 8.0);
    assert!((w.volume() - (plain - lifters)).abs() < 1e-12);
}

/// Whether `p` is in the cross-section of lifter `k` ([`Lifters::section`]): the rectangle
/// or the half disc of the tip.
fn in_section(l: &Lifters, k: usize, p: [f64; 2]) -> bool {
    let (_, c, e) = l.section(k);
    let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
    let u = dx * e[0] + dy * e[1];
    let w = dy * e[0] - dx * e[1];
    let hw = 0.5 * l.thickness;
    if u >= 0.0 {
        u <= l.radius - l.tip && w.abs() <= hw
    } else {
        u * u + w * w <= hw * hw
    }
}

#[test]
fn the_lifters_area_below_a_height_is_a_grid_count_of_their_sections() {
    let mut w = lifter_walls();
    // turned so that the line crosses the plates at a slant and through their rounded tips
    w.turn_to(0.3);
    let l = w.lifters.as_ref().unwrap();
    let hw = 0.5 * l.thickness;
    // cells of side delta over each plate's box (u from the tip's edge to R, |w| <= t/2)
    let delta = hw / 200.0;
    let (nu, nw) = (
        ((l.radius - l.tip + hw) / delta).ceil() as usize,
        (l.thickness / delta).ceil() as usize,
    );
    // a cell is miscounted only where the section's edge or the line crosses it
    let perimeter = 2.0 * (l.radius - l.tip) + l.thickness + std::f64::consts::PI * hw;
    let tolerance = l.count as f64 * (perimeter + 2.0 * (l.radius - l.tip + hw)) * delta;
    let all = l.count as f64 * l.section_area();
    assert!((l.area_below(2.0) - all).abs() < 1e-15);
    assert_eq!(l.area_below(-2.0), 0.0);
    for h in [
        -0.95, -0.5, -0.25, 0.0, 0.1, 0.24, 0.26, 0.28, 0.3, 0.5, 0.75, 0.9, 0.97,
    ] {
        let mut cells = 0u64;
        for k in 0..l.count {
            let (_, c, e) = l.section(k);
            for i in 0..nu {
                let u = l.tip - hw + (i as f64 + 0.5) * delta - l.tip;
                for j in 0..nw {
                    let ww = -hw + (j as f64 + 0.5) * delta;
                    let p = [c[0] + u * e[0] - ww * e[1], c[1] + u * e[1] + ww * e[0]];
                    if p[1] < h && in_section(l, k, p) {
                        cells += 1;
                    }
                }
            }
        }
        let counted = cells as f64 * delta * delta;
        let exact = l.area_below(h);
        assert!(
            (exact - counted).abs() < tolerance,
            "h = {h}: {exact:.6e} exact, {counted:.6e} counted (tolerance {tolerance:.1e})"
        );
    }
}

#[test]
fn the_pour_cuts_the_bed_at_its_share_of_the_free_volume() {
    // six tall, thick lifters (a tenth of the cross-section), turned off the axes
    let w = DrumWalls::of(&drum(
        "diameter = 2.0\nlength = 4.0\nends = \"capped\"\n[lifters]\ncount = 6\nheight = 0.3\nthickness = 0.1\nangle = 0.2",
    ));
    let l = w.lifters.as_ref().unwrap();
    assert!(
        (w.volume() - (4.0 * std::f64::consts::PI - 4.0 * 6.0 * l.section_area())).abs() < 1e-12
    );
    // the free cross-section below the cut, counted on a grid: inside the wall and clear of
    // every lifter
    let delta = 4e-4;
    let n = (2.0 / delta) as i64;
    for fill in [0.2, 0.3, 0.5] {
        let h = w.cut_height(fill);
        let (mut below, mut free) = (0u64, 0u64);
        for i in 0..n {
            let x = -1.0 + (i as f64 + 0.5) * delta;
            for j in 0..n {
                let y = -1.0 + (j as f64 + 0.5) * delta;
                if x * x + y * y <= 1.0 && w.inside([x, y, 0.0], 0.0) {
                    free += 1;
                    below += u64::from(y < h);
                }
            }
        }
        let share = below as f64 / free as f64;
        // cells miscounted along the wall, the lifters' edges and the line, over the free area
        let edges = 2.0 * std::f64::consts::PI + 6.0 * 2.0 * 0.3 + 2.0;
        let tolerance = edges * delta / (free as f64 * delta * delta);
        assert!(
            (share - fill).abs() < tolerance,
            "fill {fill}: cut at y = {h:.5}, {share:.5} of the free area below it \
             (tolerance {tolerance:.1e})"
        );
    }
}

#[test]
fn cone_wall_gives_the_closest_point_and_its_velocity() {
    // radius 1 at z = -1 to 0.5 at z = +1: the wall line in (rho, z) has slope -1/4
    let walls = DrumWalls::of(&drum(
        "shape = \"cone\"\ndiameter = 2.0\ndiameter_high = 1.0\nlength = 2.0",
    ));
    let cone = Cone::new(1.0, 0.5, 1.0);
    assert!((cone.radius_at(0.0) - 0.75).abs() < 1e-15);
    // a centre at z = 0 on the +y side, 0.1 in from the wall radially
    let x = V3::new(0.0, 0.65, 0.0);
    let [wall, low, high] = walls.vessel.contacts(x, 0.2);
    assert!(low.is_none() && high.is_none());
    let t = wall.unwrap();
    // inward normal (-2h, r_high - r_low)/len = (-2, -0.5)/sqrt(4.25); distance 0.1 * 2/len
    let len = 4.25f64.sqrt();
    let s = 0.1 * 2.0 / len;
    let n = V3::new(0.0, -2.0 / len, -0.5 / len);
    close(t.r, n * s, "cone: r");
    close(t.at, x - n * s, "cone: wall point");
    let rho_w = (t.at.x * t.at.x + t.at.y * t.at.y).sqrt();
    assert!(
        (rho_w - cone.radius_at(t.at.z)).abs() < 1e-14,
        "on the wall"
    );
    close(
        wall_velocity(t.at, 2.0),
        V3::new(-2.0 * t.at.y, 0.0, 0.0),
        "cone: v_wall",
    );
    // volume of a frustum; the fill below the axis of a frustum is half of it
    let v = std::f64::consts::PI * 2.0 / 3.0 * (1.0 + 0.5 + 0.25);
    assert!((walls.volume() - v).abs() < 1e-12);
    assert!((walls.fill_below(0.0) - 0.5).abs() < 1e-9);
    assert!((walls.fill_below(-1.0)).abs() < 1e-12 && (walls.fill_below(1.0) - 1.0).abs() < 1e-9);
    // inside: centre clear of the slanted wall and the caps
    assert!(walls.inside([0.0, 0.6, 0.0], 0.05));
    assert!(
        !walls.inside([0.0, 0.6, 0.9], 0.05),
        "near the high cap, outside the cone"
    );
    assert!(walls.near([0.0, 0.7, 0.0], 0.1) && !walls.near([0.0, 0.3, 0.0], 0.1));
}

/// A bead resting on the upper face of a horizontal lifter (lifter 0 along +x, its face at
/// y = t/2) of a drum that barely turns: in equilibrium the face pushes up with its weight,
/// at the overlap `m g / k_n` of the linear law.
#[test]
fn a_bead_resting_on_a_lifter_feels_its_weight() {
    let text = std::fs::read_to_string(case_path("lifters.toml")).unwrap();
    let sets: Vec<String> = [
        "drum.omega=1e-9",
        "run.rotations=1e-9",
        "model.restitution=0.3",
        "init.kind=\"particles\"",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let text = apply_overrides(&text, &sets, "stage").unwrap();
    let text = text
        .replace("fill = 0.3\n", "")
        .replace("settle_time = 0.2\n", "")
        + "\n[[init.particle]]\nspecies = 0\ndiameter = 0.004\nposition = [0.0, 0.0, 0.0]\n";
    let case = parse_case(&text, "stage").unwrap_or_else(|e| panic!("{e:?}"));
    let d = 0.004;
    let half = 0.5 * case.drum.lifters.as_ref().unwrap().thickness;
    let x0 = 0.048 - 0.002; // on the lifter (0.0455 <= x <= 0.05), clear of the curved wall
    let a = ParticleState::new(
        0,
        0,
        d,
        [x0, half + 0.5 * d + 1e-5, 0.0],
        [0.0; 3],
        [0.0; 3],
    );
    let comm = SerialComm;
    let mut sim = Sim::new(&case, &comm, &[a]).unwrap();
    for _ in 0..20_000 {
        sim.step();
    }
    let m = 1.0 / sim.p.inv_mass[0];
    let g = case.model.gravity;
    let tc = case.model.collision_time.unwrap();
    let gamma = -case.model.restitution.unwrap().ln() / tc;
    let k = m * ((std::f64::consts::PI / tc).powi(2) + gamma * gamma);
    let overlap = 0.5 * d - (sim.p.x[0][1] - half);
    assert!(
        (overlap - m * g / k).abs() < 1e-3 * m * g / k,
        "overlap {overlap:.6e} vs m g / k = {:.6e}",
        m * g / k
    );
    // the net force (wall + gravity) vanishes: the face carries the weight
    assert!(
        sim.p.f[0][1].abs() < 1e-6 * m * g,
        "net force {:?}",
        sim.p.f[0]
    );
    assert!((sim.p.x[0][0] - x0).abs() < 1e-9, "it stays put");
}

/// The fraction of particles in free flight, averaged over the samples of the second half
/// of the first rotation after the pour: touching nothing at a sample and at the sample
/// 10 ms (10 collision times) before, so that a bead of the dense flowing layer between two
/// of its frequent collisions does not count, while a bead dropped from a lifter does.
/// Returns that fraction, the fraction in free flight above the drum's axis (the shower
/// seen from the side: the bed's surface lies below it), and the fraction touching nothing
/// at one instant.
fn airborne_fraction(lifters: bool) -> (f64, f64, f64) {
    let mut case = case_with("lifters.toml", &[]);
    if !lifters {
        case.drum.lifters = None;
    }
    let comm = SerialComm;
    let (initial, scale) = initial_particles(&case, &Share::everything()).unwrap();
    let mut sim = Sim::new(&case, &comm, &initial).unwrap();
    pour::grow_settle_cut(&mut sim, &case, scale).unwrap();
    let n0 = sim.global_count();
    let [loose, n] = thermo::airborne(&sim);
    assert!(
        50 * loose < n,
        "a settled bed: {loose} of {n} beads touch nothing"
    );
    let per_rotation =
        (2.0 * std::f64::consts::PI / (case.drum.omega.abs() * sim.dt)).round() as u64;
    let every = (0.01 / sim.dt).round() as u64;
    let free = |sim: &Sim| -> std::collections::HashSet<u64> {
        let touched = thermo::in_contact(sim);
        (0..sim.p.n_owned)
            .filter(|&i| !touched[i])
            .map(|i| sim.p.id[i])
            .chain(
                (0..sim.p.n_owned)
                    .filter(|&i| !touched[i] && sim.p.x[i][1] > 0.0)
                    .map(|i| sim.p.id[i] | 1 << 50),
            )
            .collect()
    };
    let (mut before, mut flying, mut high, mut instant, mut samples) =
        (Default::default(), 0, 0, 0, 0);
    for k in 1..=per_rotation {
        sim.step();
        if k % every == 0 && k >= per_rotation / 2 - every {
            let now: std::collections::HashSet<u64> = free(&sim);
            if k >= per_rotation / 2 {
                flying += now.intersection(&before).filter(|&&i| i < 1 << 50).count();
                high += now.intersection(&before).filter(|&&i| i >= 1 << 50).count();
                instant += now.iter().filter(|&&i| i < 1 << 50).count();
                samples += sim.p.n_owned;
            }
            before = now;
        }
        if k % 1000 == 0 {
            sim.health(0.3, "the test's limit").unwrap();
        }
    }
    assert_eq!(sim.global_count(), n0, "no particle lost");
    let f = |n: usize| n as f64 / samples as f64;
    (f(flying), f(high), f(instant))
}

#[test]
fn lifters_make_the_bed_shower() {
    let (with, with_high, with_instant) = airborne_fraction(true);
    let (without, without_high, without_instant) = airborne_fraction(false);
    let report = format!(
        "in free flight: {with:.4} with lifters, {without:.4} without; above the axis: \
         {with_high:.4} with, {without_high:.4} without; touching nothing at an instant: \
         {with_instant:.4} with, {without_instant:.4} without"
    );
    println!("{report}");
    assert!(with > 1.8 * without && with > 0.1, "{report}");
    assert!(with_high > 3.0 * without_high, "{report}");
}

/// Every particle touching a wall is in the near-wall list at every step, for `steps` steps
/// of `sim`; returns how many particle-steps touched a wall (so that a test can tell that the
/// check checked something).
fn near_wall_list_holds(sim: &mut Sim, steps: u64) -> u64 {
    let mut touching = 0;
    for _ in 0..steps {
        sim.step();
        let missed = sim.wall_contacts_unlisted();
        assert!(
            missed.is_empty(),
            "step {}: particles {missed:?} touch a wall but are not listed near one",
            sim.step
        );
        touching += (0..sim.p.n_owned)
            .filter(|&i| {
                let reach = sim.law.wall_reach(sim.p.diameter[i] * sim.scale);
                sim.walls.touches(sim.p.x[i], reach)
            })
            .count() as u64;
    }
    touching
}

#[test]
fn the_near_wall_list_holds_between_builds() {
    // lifters (listed over the annulus they sweep), caps and the curved wall, with and
    // without contact histories; a cone and a sphere: each poured, then turned
    for file in ["lifters.toml", "sd_capped.toml", "cone.toml", "sphere.toml"] {
        let case = case_with(file, &[]);
        let comm = SerialComm;
        let (initial, scale) = initial_particles(&case, &Share::everything()).unwrap();
        let mut sim = Sim::new(&case, &comm, &initial).unwrap();
        pour::grow_settle_cut(&mut sim, &case, scale).unwrap();
        let builds = sim.rebuilds;
        let touching = near_wall_list_holds(&mut sim, 1500);
        let builds = sim.rebuilds - builds;
        println!("{file}: {touching} particle-steps touching a wall, {builds} builds");
        assert!(
            touching > 1500 * 20,
            "{file}: {touching} particle-steps touching a wall"
        );
        assert!(builds > 2, "{file}: {builds} builds");
    }
}

#[test]
fn a_bed_in_a_cone_stays_inside_and_keeps_its_particles() {
    let case = case_with("cone.toml", &["run.rotations=0.2"]);
    let comm = SerialComm;
    let (initial, scale) = initial_particles(&case, &Share::everything()).unwrap();
    let mut sim = Sim::new(&case, &comm, &initial).unwrap();
    let report = pour::grow_settle_cut(&mut sim, &case, scale).unwrap();
    assert!(report.kept > 500, "{} kept", report.kept);
    assert!(
        (report.measured_fill - 0.3).abs() < 0.05,
        "fill {}",
        report.measured_fill
    );
    let steps = (0.2 * 2.0 * std::f64::consts::PI / (case.drum.omega * sim.dt)) as u64;
    let walls = DrumWalls::of(&case.drum);
    for k in 0..steps {
        sim.step();
        if k % 500 == 0 || k + 1 == steps {
            sim.health(0.2, "the test's limit").unwrap();
            for i in 0..sim.p.n_owned {
                let r = 0.5 * sim.p.diameter[i];
                // no centre further into a wall than 20 % of its diameter
                assert!(
                    walls.inside(sim.p.x[i], 0.6 * r),
                    "particle {} at {:?}",
                    sim.p.id[i],
                    sim.p.x[i]
                );
            }
        }
    }
    assert_eq!(sim.global_count(), report.kept, "particles conserved");
    // the bed is deeper at the wide end (z < 0)
    let (mut low, mut high) = (0, 0);
    for x in &sim.p.x[..sim.p.n_owned] {
        if x[2] < 0.0 {
            low += 1
        } else {
            high += 1
        }
    }
    assert!(
        low > 2 * high,
        "{low} particles in the wide half, {high} in the narrow one"
    );
}

fn refused(sets: &[&str], parts: &[&str]) {
    let case = case_path("lifters.toml");
    let mut args = vec!["check", case.to_str().unwrap()];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = tumbler(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{sets:?}: {err}");
    for p in parts {
        assert!(err.contains(p), "{sets:?}: `{p}` not in {err}");
    }
}

#[test]
fn bad_lifter_and_cone_keys_are_refused() {
    refused(
        &["drum.lifters.height=0.06"],
        &["drum.lifters.height", "radius"],
    );
    refused(
        &["drum.lifters.height=-0.01"],
        &["drum.lifters.height", "positive"],
    );
    refused(
        &["drum.lifters.height=nan"],
        &["drum.lifters.height", "finite"],
    );
    refused(
        &["drum.lifters.thickness=0.02"],
        &["drum.lifters.thickness", "at most the height"],
    );
    refused(
        &["drum.lifters.count=0"],
        &["drum.lifters.count", "1 to 360"],
    );
    refused(
        &["drum.lifters.count=60"],
        &["drum.lifters.count", "touch two", "one contact history"],
    );
    refused(&["drum.lifters.span=[0.0, 0.5]"], &["drum.lifters.span"]);
    refused(
        &["drum.shape=\"sphere\"", "drum.length=nan"],
        &["drum.lifters", "cylinder"],
    );
    refused(
        &["drum.shape=\"cone\"", "drum.ends=\"capped\""],
        &["drum.diameter_high", "required"],
    );
    refused(
        &["drum.shape=\"cone\"", "drum.diameter_high=0.2"],
        &["drum.diameter_high", "at most drum.diameter"],
    );
    refused(
        &["drum.diameter_high=0.05"],
        &["drum.diameter_high", "cone only"],
    );
}

#[test]
fn check_reports_the_lifters() {
    let case = case_path("lifters.toml");
    let o = tumbler(&["check", case.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("6 lifters 0.01 high"), "{out}");
}
