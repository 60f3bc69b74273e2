//! The diagnostics on synthetic particle sets with known answers: solid-body rotation,
//! a uniform mixture, a prescribed axial drift against a concentration gradient, axial
//! flows that change sign across the surface, and a flat bed at a known tilt.

mod common;

use common::case_with;
use tumbler::case::Case;
use tumbler::comm::SerialComm;
use tumbler::diag::surface::Frame;
use tumbler::diag::{AxialBins, Windows};
use tumbler::particles::{ParticleState, Particles};
use tumbler::physics::Materials;

/// Lattice points (spacing `h`) inside the drum of `case` below `y_top`, passed to `make`,
/// which returns the particles to put there.
fn fill(
    case: &Case,
    h: f64,
    y_top: f64,
    make: &mut dyn FnMut([f64; 3]) -> Vec<(u8, f64, [f64; 3])>,
) -> Particles {
    let mat = Materials::new(case);
    let r = 0.5 * case.drum.diameter - case.d_max();
    let half = 0.5 * case.drum.axial_length();
    let mut p = Particles::default();
    let n = (2.0 * half / h) as i64;
    let m = (2.0 * r / h) as i64 + 1;
    let mut id = 0;
    for k in 0..n {
        let z = -half + (k as f64 + 0.5) * h;
        for i in -m..=m {
            for j in -m..=m {
                let (x, y) = (i as f64 * h + 0.25 * h, j as f64 * h + 0.25 * h);
                if x * x + y * y > r * r || y > y_top {
                    continue;
                }
                for (s, d, v) in make([x, y, z]) {
                    p.push_owned(&ParticleState::new(id, s, d, [x, y, z], v, [0.0; 3]), &mat);
                    id += 1;
                }
            }
        }
    }
    p
}

fn windows(case: &Case) -> (AxialBins, Windows) {
    let d = case.d_max();
    let axial = AxialBins::new(
        case.drum.axial_length(),
        case.slice_width(),
        case.species.len(),
        d,
        1.0,
    );
    let w = Windows::new(case, &axial);
    (axial, w)
}

fn drum(overrides: &[&str]) -> Case {
    case_with("sd_capped.toml", overrides)
}

#[test]
fn solid_body_rotation_gives_omega_cross_r_in_every_bin_and_no_fluctuations() {
    for omega in [6.0, -6.0] {
        solid_body(omega);
    }
}

fn solid_body(omega: f64) {
    let case = drum(&[
        "diagnostics.surface_angle=25.0",
        &format!("drum.omega={omega}"),
    ]);
    let omega = case.drum.omega;
    let d = case.species[0].diameter;
    let p = fill(&case, 0.001, 0.0, &mut |x| {
        vec![(0, d, [-omega * x[1], omega * x[0], 0.0])]
    });
    let (_, mut w) = windows(&case);
    let comm = SerialComm;
    w.sample(&p, &comm);
    w.sample(&p, &comm);
    let f = w.flush_fields(&comm).unwrap();
    // expected: the mean of each bin's particle velocities, in surface-frame components
    let frame = Frame::new(25.0, omega);
    let grid = &w.fields.grid;
    let nb = grid.bins();
    let mut sum = vec![[0.0; 3]; nb];
    let mut n = vec![0.0; nb];
    for i in 0..p.n_owned {
        let (xs, ys) = frame.project(p.x[i][0], p.x[i][1]);
        let b = grid.index(xs, ys, p.x[i][2]);
        let (u, v) = frame.project(p.v[i][0], p.v[i][1]);
        for (a, c) in sum[b].iter_mut().zip([u, v, p.v[i][2]]) {
            *a += c;
        }
        n[b] += 1.0;
    }
    let scale = omega.abs() * 0.5 * case.drum.diameter;
    let mut checked = 0;
    for b in 0..nb {
        if n[b] == 0.0 {
            assert!(f.velocity[b].is_nan(), "empty bin {b} has a velocity");
            continue;
        }
        checked += 1;
        for (k, total) in sum[b].iter().enumerate() {
            let want = total / n[b];
            let got = f.velocity[k * nb + b];
            assert!(
                (got - want).abs() < 1e-9 * scale,
                "bin {b} component {k}: {got} vs omega x r = {want}"
            );
            assert!(f.velocity_drum[k * nb + b].abs() < 1e-9 * scale);
            assert!(
                f.rms[k * nb + b] < 1e-6 * scale,
                "rms {}",
                f.rms[k * nb + b]
            );
        }
    }
    assert!(checked > 100, "only {checked} bins held particles");
    // nothing flows in the drum frame
    assert!(f.u0.abs() < 1e-9 * scale);
    assert_eq!(f.angle, 25.0);
}

#[test]
fn a_uniform_mixture_has_c_s_one_half_everywhere() {
    let case = drum(&[]);
    let d = case.species[0].diameter;
    // both species at every lattice point, same size
    let p = fill(&case, 0.0012, 0.0, &mut |_| {
        vec![(0, d, [0.0; 3]), (1, d, [0.0; 3])]
    });
    let (axial, mut w) = windows(&case);
    let comm = SerialComm;
    w.sample(&p, &comm);
    let r = w.flush_slices(&comm).unwrap();
    let nz = axial.nz;
    for k in 0..nz {
        assert!((r.slices.concentration[k] - 0.5).abs() < 1e-12, "slice {k}");
        assert!((r.slices.concentration[nz + k] - 0.5).abs() < 1e-12);
    }
    let s = axial.gather(&p, &comm).unwrap();
    assert!(s.volume_fraction[..nz]
        .iter()
        .all(|c| (c - 0.5).abs() < 1e-12));
}

#[test]
fn drift_against_a_concentration_gradient_gives_a_negative_diffusivity() {
    let case = drum(&["diagnostics.surface_angle=0.0"]);
    let (axial, mut w) = windows(&case);
    let (d1, u) = (0.002, 0.01);
    let half = 0.5 * case.drum.axial_length();
    // species 0 grows along z: its concentration rises with z; it drifts towards +z
    let d0 = |z: f64| {
        let k = ((z + half) / axial.width).floor();
        0.0015 + 0.001 * (k + 0.5) * axial.width / (2.0 * half)
    };
    let p = fill(&case, 0.001, 0.0, &mut |x| {
        vec![(0, d0(x[2]), [0.0, 0.0, u]), (1, d1, [0.0, 0.0, -u])]
    });
    let comm = SerialComm;
    w.sample(&p, &comm);
    let r = w.flush_slices(&comm).unwrap().slices;
    let nz = axial.nz;
    let c: Vec<f64> = axial
        .centres()
        .iter()
        .map(|&z| d0(z).powi(3) / (d0(z).powi(3) + d1 * d1 * d1))
        .collect();
    for k in 1..nz - 1 {
        assert!((r.concentration[k] - c[k]).abs() < 1e-9);
        let rel = 2.0 * c[k] * (1.0 - c[k]) * u;
        assert!((r.relative_flux[k] - rel).abs() < 1e-9 * u, "slice {k}");
        let grad = (c[k + 1] - c[k - 1]) / (2.0 * axial.width);
        assert!(grad > 0.0);
        let k_want = -rel / grad;
        assert!(
            r.diffusivity[k] < 0.0,
            "slice {k}: K = {}",
            r.diffusivity[k]
        );
        assert!(
            (r.diffusivity[k] - k_want).abs() < 1e-6 * k_want.abs(),
            "slice {k}: K = {} vs {k_want}",
            r.diffusivity[k]
        );
        // the other species diffuses the other way with the same K
        assert!((r.diffusivity[nz + k] - k_want).abs() < 1e-6 * k_want.abs());
    }
}

#[test]
fn axial_flow_that_changes_sign_across_the_layer_splits_into_up_and_downstream() {
    let case = drum(&["diagnostics.surface_angle=0.0"]);
    let omega = case.drum.omega;
    let frame = Frame::new(0.0, omega);
    let (axial, mut w) = windows(&case);
    let (d, u) = (case.species[0].diameter, 0.02);
    // upstream (surface-frame x < 0) flows to +z, downstream back to -z
    let p = fill(&case, 0.001, 0.0, &mut |x| {
        let (xs, _) = frame.project(x[0], x[1]);
        let s = if x[2] < 0.0 { 0 } else { 1 };
        vec![(s, d, [0.0, 0.0, if xs < 0.0 { u } else { -u }])]
    });
    let comm = SerialComm;
    w.sample(&p, &comm);
    let r = w.flush_slices(&comm).unwrap().slices;
    let nz = axial.nz;
    // expected: the particle volume on each side times u over slice width and packing
    let mut up = vec![0.0; nz];
    for i in 0..p.n_owned {
        let (xs, _) = frame.project(p.x[i][0], p.x[i][1]);
        let k = (((p.x[i][2] + 0.5 * case.drum.axial_length()) / axial.width) as usize).min(nz - 1);
        if xs < 0.0 {
            up[k] += std::f64::consts::PI / 6.0 * d * d * d * u / (axial.width * 0.64);
        }
    }
    for (k, &up) in up.iter().enumerate() {
        assert!(
            r.q_up_mixture[k] > 0.0 && r.q_down_mixture[k] < 0.0,
            "slice {k}"
        );
        assert!(
            (r.q_up_mixture[k] - up).abs() < 1e-9 * up,
            "slice {k}: {} vs {}",
            r.q_up_mixture[k],
            up
        );
        // the bed is symmetric about x = 0: up and down balance
        assert!((r.q_up_mixture[k] + r.q_down_mixture[k]).abs() < 0.05 * up);
    }
    // every row holding particles has its sign change at x = 0
    let rows_with_sign: usize = r.split_by_sign.iter().map(|&b| b as usize).sum();
    let rows = r.split_x.iter().filter(|x| x.is_finite()).count();
    assert!(rows >= 4 * nz, "only {rows} rows hold particles");
    assert_eq!(rows_with_sign, rows);
    assert!(r
        .split_x
        .iter()
        .filter(|x| x.is_finite())
        .all(|x| x.abs() < 1e-12));
    // per species: species 0 only in z < 0
    assert!(r.q_up[nz - 1] == 0.0 && r.q_up[nz] == 0.0);
}

#[test]
fn a_flat_bed_at_a_known_tilt_gives_that_angle_of_repose() {
    use rand::{Rng, SeedableRng};
    for (omega, theta) in [(6.0f64, 30.0f64), (-6.0, 22.0)] {
        let case = drum(&[&format!("drum.omega={omega}"), "output.slice_width=0.004"]);
        let mat = Materials::new(&case);
        let big_r = 0.5 * case.drum.diameter;
        let half = 0.5 * case.drum.axial_length();
        let d = 0.0004;
        let slope = theta.to_radians().tan() * omega.signum();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut p = Particles::default();
        let mut id = 0;
        while id < 60_000 {
            let x = rng.gen_range(-big_r..big_r);
            let y = rng.gen_range(-big_r..big_r);
            let z = rng.gen_range(-half..half);
            if x * x + y * y > (big_r - d) * (big_r - d) || y + 0.5 * d > slope * x - 0.3 * big_r {
                continue;
            }
            p.push_owned(
                &ParticleState::new(id, 0, d, [x, y, z], [0.0; 3], [0.0; 3]),
                &mat,
            );
            id += 1;
        }
        let case = {
            let mut c = case.clone();
            c.species[0].diameter = d;
            c.species[1].diameter = d;
            c
        };
        let (_, w) = windows(&case);
        let a = w.measure(&p, &SerialComm);
        assert!(
            (a.drum - theta).abs() < 0.5,
            "omega {omega}: {} vs {theta}",
            a.drum
        );
        for (k, s) in a.slice.iter().enumerate() {
            assert!((s - theta).abs() < 3.0, "slice {k}: {s} vs {theta}");
        }
    }
}

#[test]
fn snapshots_come_with_an_xdmf_file_that_names_datasets_in_the_hdf5_file() {
    let dir = common::tmpdir();
    let out = dir.path().join("snap.h5");
    let case = common::case_path("sd_capped.toml");
    let o = common::mpirun(
        2,
        &[
            "run",
            case.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "run.rotations=0.05",
            "--set",
            "diagnostics.snapshots.every=0.02",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(dir.path().join("snap.xmf")).unwrap();
    let doc = roxmltree::Document::parse_with_options(
        &text,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .expect("the XDMF file is well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "Xdmf");
    let f = hdf5::File::open(&out).unwrap();
    let grids: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("Grid") && n.attribute("Name") == Some("particles"))
        .collect();
    // step 0, 0.02 and 0.04 rotations
    assert_eq!(grids.len(), 3);
    let mut items = 0;
    for g in &grids {
        // the connectivity of a particle count is written once, then included
        let included = |g: roxmltree::Node| {
            let x = g.children().find(|n| n.tag_name().name() == "include")?;
            let step = x.attribute("xpointer")?.split('\'').nth(1)?.to_string();
            doc.descendants()
                .find(|n| n.attribute("Name") == Some(step.as_str()))?
                .descendants()
                .find(|n| n.has_tag_name("Topology"))
        };
        let n: usize = g
            .descendants()
            .find(|n| n.has_tag_name("Topology"))
            .or_else(|| included(*g))
            .and_then(|t| t.attribute("NumberOfElements"))
            .unwrap()
            .parse()
            .unwrap();
        for item in g
            .descendants()
            .filter(|n| n.has_tag_name("DataItem") && n.attribute("Format") == Some("HDF"))
        {
            let (file, path) = item.text().unwrap().trim().split_once(':').unwrap();
            assert_eq!(file, "snap.h5");
            let ds = f.dataset(path).unwrap_or_else(|_| {
                panic!("{path} named in the XDMF file is not in the HDF5 file")
            });
            assert_eq!(ds.shape()[0], n, "{path}");
            let dims: Vec<usize> = item
                .attribute("Dimensions")
                .unwrap()
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            assert_eq!(dims, ds.shape(), "{path}");
            items += 1;
        }
    }
    assert_eq!(items, 3 * 6);
}

#[test]
fn a_linear_shear_layer_has_its_flowing_boundary_where_the_velocity_falls_to_5_percent() {
    let case = drum(&[
        "diagnostics.surface_angle=0.0",
        "diagnostics.fields.grid=[30, 60, 4]",
    ]);
    let omega = case.drum.omega;
    let frame = Frame::new(0.0, omega);
    let (u_s, delta, h) = (0.1, 0.004, 0.0005);
    let d = case.species[0].diameter;
    // drum frame: u = u_s (1 + y/delta) in the top delta of the bed, at rest below
    let u_of = |y: f64| u_s * (1.0 + y / delta).max(0.0);
    let p = fill(&case, h, 0.0, &mut |x| {
        let u = u_of(x[1]);
        let v = [
            -omega * x[1] + u * frame.ex[0],
            omega * x[0] + u * frame.ex[1],
            0.0,
        ];
        vec![(0, d, v)]
    });
    let (_, mut w) = windows(&case);
    let comm = SerialComm;
    w.sample(&p, &comm);
    let f = w.flush_fields(&comm).unwrap();
    let grid = &w.fields.grid;
    let dy = grid.size[1];
    // the top row of particles is at y = -0.75 h, in the bin [-dy, 0]
    let u0 = u_of(-0.75 * h);
    assert!((f.u0 - u0).abs() < 1e-9, "u0 {} vs {u0}", f.u0);
    let want = delta * (0.05 * u0 / u_s - 1.0);
    let nz = grid.n[2];
    let xs = grid.centres(0);
    let mut checked = 0;
    for (ix, x) in xs.iter().enumerate() {
        // columns well inside the bed
        if x.abs() > 0.008 {
            continue;
        }
        for iz in 0..nz {
            let c = ix * nz + iz;
            assert!(f.surface[c].abs() < 1e-12, "surface {}", f.surface[c]);
            assert!(
                (f.boundary[c] - want).abs() < 0.6 * dy,
                "column {ix},{iz}: boundary {} vs {want}",
                f.boundary[c]
            );
            assert!((f.depth[c] - (f.surface[c] - f.boundary[c])).abs() < 1e-15);
            checked += 1;
        }
    }
    assert!(checked >= 16);
}

#[test]
fn windows_paths_and_their_times_follow_the_schedule() {
    use tumbler::run::steps_for;
    let dir = common::tmpdir();
    let out = dir.path().join("sched.h5");
    let case_file = common::case_path("sd_capped.toml");
    let o = common::mpirun(
        2,
        &[
            "run",
            case_file.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "run.rotations=0.047",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let case = drum(&[]);
    let (omega, dt) = (case.drum.omega, case.dt());
    let g = &case.diagnostics;
    let total = steps_for(0.047, omega, dt);
    // a window is a whole number of samples, and window k ends on the step nearest k
    // windows of rotations: sample j is due at j / per windows
    let per = (g.window / g.sample_every).round() as u64;
    let per_fields = (g.fields.window / g.sample_every).round() as u64;
    let due = |j: u64| (j / per) as f64 * g.window + (j % per) as f64 * (g.window / per as f64);
    let sample_step = |j: u64| steps_for(due(j), omega, dt);
    let taken = (1..).take_while(|&j| sample_step(j) <= total).count() as u64;
    let paths = steps_for(g.paths.every.unwrap(), omega, dt);
    let rot = |s: u64| s as f64 * dt * omega.abs() / (2.0 * std::f64::consts::PI);
    let step_rot = rot(1);
    let f = hdf5::File::open(&out).unwrap();
    let read = |n: &str| -> Vec<f64> { f.dataset(n).unwrap().read_raw().unwrap() };
    let count = |n: &str| -> Vec<u64> { f.dataset(n).unwrap().read_raw().unwrap() };
    let attr = |g: &str| -> u64 {
        f.group(g)
            .unwrap()
            .attr("samples_per_window")
            .unwrap()
            .read_scalar()
            .unwrap()
    };
    assert_eq!(attr("slices"), per);
    assert_eq!(attr("fields"), per_fields);
    // whole windows, then the partial last one
    let mut starts = Vec::new();
    let mut ends = Vec::new();
    let mut samples = Vec::new();
    let mut j = 0;
    while j < taken {
        let e = (j + per).min(taken);
        starts.push(rot(sample_step(j)));
        ends.push(rot(if e == taken { total } else { sample_step(e) }));
        samples.push(e - j);
        j = e;
    }
    assert!(samples.len() >= 3, "{samples:?}");
    assert_eq!(read("slices/rotations_start"), starts);
    assert_eq!(read("slices/rotations_end"), ends);
    assert_eq!(count("slices/samples"), samples);
    // every whole window is the window's rotations to within a step, and ends within half
    // a step of a whole number of windows: no drift
    for (k, (a, b)) in starts.iter().zip(&ends).enumerate().take(samples.len() - 1) {
        assert_eq!(samples[k], per);
        assert!((b - a - g.window).abs() <= step_rot * 1.0001, "{a} {b}");
        let whole = (k + 1) as f64 * g.window;
        assert!(
            (b - whole).abs() <= 0.5001 * step_rot,
            "window {k} ends at {b}"
        );
    }
    assert!(
        *samples.last().unwrap() < per,
        "the last window is partial here"
    );
    let fields = sample_step(per_fields);
    assert!(fields > total);
    assert_eq!(read("fields/rotations_end"), vec![rot(total)]);
    assert_eq!(count("fields/samples"), vec![taken]);
    // the last window ends at the last axial sample, the same number
    assert_eq!(read("axial/rotations").last(), ends.last());
    // paths from step 0
    let want: Vec<f64> = (0..=total / paths).map(|k| rot(k * paths)).collect();
    assert_eq!(read("paths/rotations"), want);
    let np = f.dataset("paths/id").unwrap().shape()[0];
    assert!(np > 10, "only {np} particles followed");
    assert_eq!(
        f.dataset("paths/position").unwrap().shape(),
        vec![want.len(), np, 3]
    );
}
