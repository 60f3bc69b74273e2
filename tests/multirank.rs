//! Decomposition invariance, the project's central test: runs on 1, 2 and 3 ranks (`mpirun`)
//! of the same case give bit-identical particle states, axial profiles, diagnostics and
//! thermo columns (all but the rate), with particles crossing slab faces (and the periodic
//! ends) on the way.

mod common;

use common::{case_path, mpirun, tmpdir};
use std::path::Path;

struct Snapshot {
    id: Vec<u64>,
    species: Vec<u8>,
    diameter: Vec<f64>,
    position: Vec<f64>,
    velocity: Vec<f64>,
    angular_velocity: Vec<f64>,
    volume_fraction: Vec<f64>,
    count: Vec<u64>,
    rotations: Vec<f64>,
    migrations: u64,
    histories_migrated: u64,
    ranks: u64,
}

fn read(path: &Path) -> Snapshot {
    let f = hdf5::File::open(path).unwrap();
    let v = |name: &str| f.dataset(name).unwrap().read_raw::<f64>().unwrap();
    Snapshot {
        id: f.dataset("particles/id").unwrap().read_raw().unwrap(),
        species: f.dataset("particles/species").unwrap().read_raw().unwrap(),
        diameter: v("particles/diameter"),
        position: v("particles/position"),
        velocity: v("particles/velocity"),
        angular_velocity: v("particles/angular_velocity"),
        volume_fraction: v("axial/volume_fraction"),
        count: f.dataset("axial/count").unwrap().read_raw().unwrap(),
        rotations: v("axial/rotations"),
        migrations: f.attr("migrations").unwrap().read_scalar().unwrap(),
        histories_migrated: f.attr("histories_migrated").unwrap().read_scalar().unwrap(),
        ranks: f.attr("ranks").unwrap().read_scalar().unwrap(),
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn run_on(ranks: usize, case: &str, dir: &Path, extra: &[&str]) -> Snapshot {
    let out = dir.join(format!("{case}.{ranks}.h5"));
    let case_file = case_path(case);
    let mut args = vec![
        "run",
        case_file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = mpirun(ranks, &args);
    assert!(
        o.status.success(),
        "{ranks} ranks failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    read(&out)
}

fn assert_identical(case: &str) -> Vec<Snapshot> {
    assert_identical_on(case, &[2, 3])
}

fn assert_identical_on(case: &str, rank_counts: &[usize]) -> Vec<Snapshot> {
    assert_identical_with(case, rank_counts, &[], &tmpdir())
}

/// Runs `case` with the overrides `extra` on one rank and on each of `rank_counts`, in `dir`
/// (kept for the caller to read the outputs `CASE.RANKS.h5`), and asserts the same bits.
fn assert_identical_with(
    case: &str,
    rank_counts: &[usize],
    extra: &[&str],
    dir: &tempfile::TempDir,
) -> Vec<Snapshot> {
    let one = run_on(1, case, dir.path(), extra);
    let n = one.id.len();
    assert!(n > 300, "{case}: only {n} particles");
    // sorted, each once (a pour keeps only the ids below its cut)
    assert!(
        one.id.windows(2).all(|w| w[0] < w[1]),
        "ids sorted, each once"
    );
    let mut others = Vec::new();
    for &ranks in rank_counts {
        let other = run_on(ranks, case, dir.path(), extra);
        assert_eq!(other.ranks, ranks as u64);
        assert!(
            other.migrations > 50,
            "{case} on {ranks} ranks: only {} particles crossed a slab face",
            other.migrations
        );
        assert_eq!(one.id, other.id, "{case} on {ranks} ranks: ids");
        assert_eq!(one.species, other.species);
        assert_eq!(bits(&one.diameter), bits(&other.diameter));
        for (name, a, b) in [
            ("position", &one.position, &other.position),
            ("velocity", &one.velocity, &other.velocity),
            (
                "angular_velocity",
                &one.angular_velocity,
                &other.angular_velocity,
            ),
        ] {
            let differing = a
                .iter()
                .zip(b)
                .filter(|(x, y)| x.to_bits() != y.to_bits())
                .count();
            assert_eq!(
                differing, 0,
                "{case}: {name} differs in {differing} components on {ranks} ranks vs 1"
            );
        }
        assert_eq!(
            bits(&one.volume_fraction),
            bits(&other.volume_fraction),
            "{case}: axial volume fractions"
        );
        assert_eq!(one.count, other.count, "{case}: axial counts");
        assert_eq!(bits(&one.rotations), bits(&other.rotations));
        common::assert_same_diagnostics(
            &dir.path().join(format!("{case}.1.h5")),
            &dir.path().join(format!("{case}.{ranks}.h5")),
            &format!("{case} on {ranks} ranks vs 1"),
        );
        // every thermo column but the rate (wall clock), the airborne fraction among them
        let log =
            |r: usize| std::fs::read_to_string(dir.path().join(format!("{case}.{r}.log"))).unwrap();
        let (log1, logn) = (log(1), log(ranks));
        let (t1, tn) = (common::thermo_bits(&log1), common::thermo_bits(&logn));
        assert!(t1.len() >= 2, "{case}: thermo lines\n{log1}");
        assert_eq!(
            t1, tn,
            "{case}: thermo on {ranks} ranks vs 1\n{log1}\n{logn}"
        );
        others.push(other);
    }
    others
}

#[test]
fn periodic_drum_is_bit_identical_on_1_2_3_4_6_8_ranks() {
    assert_identical_on("periodic.toml", &[2, 3, 4, 6, 8]);
}

#[test]
fn capped_drum_is_bit_identical_on_1_2_3_4_6_8_ranks() {
    assert_identical_on("capped.toml", &[2, 3, 4, 6, 8]);
}

#[test]
fn history_model_pour_and_drum_are_bit_identical_on_1_2_3_ranks() {
    // Pour fill (grown, settled and cut in the engine), then the turning drum with
    // Cundall-Strack histories: loaded contacts span the slab faces and travel with
    // migrating particles.
    assert_histories_migrated(&assert_identical("sd_capped.toml"));
}

/// Asserts that on every rank count more than 100 contact histories moved with migrating
/// particles: the runs did test histories crossing slab faces.
fn assert_histories_migrated(others: &[Snapshot]) {
    for other in others {
        assert!(
            other.histories_migrated > 100,
            "on {} ranks only {} contact histories moved with migrating particles",
            other.ranks,
            other.histories_migrated
        );
    }
}

/// Asserts that by the last load-balance check of `CASE.RANKS.h5` in `dir`, for each of
/// `rank_counts`, an inner boundary lies more than 5 % of a slab from where equal slabs put it.
fn assert_boundaries_moved(dir: &Path, case: &str, rank_counts: &[usize]) {
    for &ranks in rank_counts {
        let f = hdf5::File::open(dir.join(format!("{case}.{ranks}.h5"))).unwrap();
        let b = f.dataset("balance/bounds").unwrap();
        let rows = b.shape()[0];
        let all: Vec<f64> = b.read_raw().unwrap();
        let last = &all[(rows - 1) * (ranks + 1)..];
        let (lo, hi) = (last[0], last[ranks]);
        let width = (hi - lo) / ranks as f64;
        let moved = (1..ranks)
            .map(|k| ((last[k] - (lo + k as f64 * width)) / width).abs())
            .fold(0.0, f64::max);
        assert!(
            moved > 0.05,
            "{case} on {ranks} ranks: the boundaries stayed where equal slabs put them: {last:?}"
        );
    }
}

/// Asserts that in `CASE.RANKS.h5` in `dir`, for each of `rank_counts`, at least two
/// load-balance checks moved the slab boundaries (the first from equal slabs).
fn assert_rebalanced(dir: &Path, case: &str, rank_counts: &[usize]) {
    for &ranks in rank_counts {
        let f = hdf5::File::open(dir.join(format!("{case}.{ranks}.h5"))).unwrap();
        let all: Vec<f64> = f.dataset("balance/bounds").unwrap().read_raw().unwrap();
        let rows: Vec<&[f64]> = all.chunks_exact(ranks + 1).collect();
        let (lo, hi) = (rows[0][0], rows[0][ranks]);
        let width = (hi - lo) / ranks as f64;
        let equal: Vec<f64> = (0..=ranks).map(|k| lo + k as f64 * width).collect();
        let differ =
            |a: &[f64], b: &[f64]| a.iter().zip(b).any(|(x, y)| (x - y).abs() > 1e-9 * width);
        let mut moves = 0;
        let mut last: &[f64] = &equal;
        for row in &rows {
            moves += differ(row, last) as usize;
            last = row;
        }
        assert!(
            moves >= 2,
            "{case} on {ranks} ranks: the boundaries moved at {moves} of {} checks",
            rows.len()
        );
    }
}

#[test]
fn history_model_with_balancing_is_bit_identical_on_4_6_8_ranks() {
    // The Cundall-Strack drum with the slab boundaries moving every 0.02 rotations:
    // particles and their loaded contact histories migrate to whichever rank now owns them.
    // This capped drum is nearly even along its axis (max / mean work per rank about 1.01
    // to 1.05 on equal slabs): a tolerance of 1 moves the boundaries at every check that
    // can even the work out better.
    let dir = tmpdir();
    let extra = [
        "--set",
        "run.balance_every=0.02",
        "--set",
        "run.balance_tolerance=1.0",
    ];
    assert_histories_migrated(&assert_identical_with(
        "sd_capped.toml",
        &[4, 6, 8],
        &extra,
        &dir,
    ));
    assert_rebalanced(dir.path(), "sd_capped.toml", &[4, 6, 8]);
}

/// `sd_capped.toml` with the rolling spring (6 history words per contact) and cohesion,
/// different for the two species and the walls, per-species restitutions and a
/// `[[pairs]]` override of the mixed pair (each pair then has its own normal
/// coefficients), turning twice as long (the rolling resistance keeps the bed together, so
/// fewer contacts cross a face per rotation). The last four words are the length and the
/// balancing alone.
pub const ROLLING_COHESION: [&str; 22] = [
    "--set",
    "model.rolling=\"sds\"",
    "--set",
    "species.0.mu_roll=0.1",
    "--set",
    "species.1.mu_roll=0.15",
    "--set",
    "model.cohesion=\"sjkr\"",
    "--set",
    "species.0.cohesion_energy=500.0",
    "--set",
    "species.1.cohesion_energy=800.0",
    "--set",
    "species.0.restitution=0.8",
    "--set",
    "species.1.restitution_wall=0.7",
    "--set",
    "pairs=[{species=[\"small\", \"large\"], restitution=0.75, mu=0.4, mu_roll=0.12, cohesion_energy=600.0}]",
    "--set",
    "run.rotations=0.2",
    "--set",
    "run.balance_every=0.02",
];

#[test]
fn rolling_and_cohesion_sub_models_with_balancing_are_bit_identical_on_1_2_3_4_ranks() {
    // contacts carry six history words (tangential and rolling springs) through the list,
    // the halo's migrations and the moving boundaries; each pair has its own normal
    // coefficients
    let dir = tmpdir();
    let others = assert_identical_with("sd_capped.toml", &[2, 3, 4], &ROLLING_COHESION, &dir);
    assert_histories_migrated(&others);
    // the sub-models act: the same run without them ends elsewhere
    let d2 = tmpdir();
    let plain = run_on(
        1,
        "sd_capped.toml",
        d2.path(),
        &ROLLING_COHESION[ROLLING_COHESION.len() - 4..],
    );
    let with = read(&dir.path().join("sd_capped.toml.1.h5"));
    assert_ne!(bits(&plain.position), bits(&with.position));
}

#[test]
fn periodic_history_drum_with_balancing_is_bit_identical_on_1_2_3_4_6_8_ranks() {
    // Histories across the periodic seam as well as the slab faces, boundaries moving.
    let dir = tmpdir();
    let extra = ["--set", "run.balance_every=0.02"];
    assert_histories_migrated(&assert_identical_with(
        "sd_periodic.toml",
        &[2, 3, 4, 6, 8],
        &extra,
        &dir,
    ));
}

#[test]
fn spherical_tumbler_with_balancing_is_bit_identical_on_4_6_8_ranks() {
    // In a sphere the end slabs hold few particles: balancing widens them and narrows the
    // middle ones, never below the interaction range + skin.
    let dir = tmpdir();
    let extra = ["--set", "run.balance_every=0.01"];
    assert_identical_with("sphere.toml", &[4, 6, 8], &extra, &dir);
    assert_boundaries_moved(dir.path(), "sphere.toml", &[4, 6, 8]);
}

#[test]
fn rough_wall_drum_with_balancing_is_bit_identical_on_2_and_3_ranks() {
    // 3 ranks is as many slabs as this short drum can be cut into.
    let dir = tmpdir();
    let extra = ["--set", "run.balance_every=0.02"];
    assert_identical_with("rough.toml", &[2, 3], &extra, &dir);
}

#[test]
fn rough_wall_drum_is_bit_identical_on_1_2_3_ranks() {
    assert_identical("rough.toml");
}

#[test]
fn spherical_tumbler_is_bit_identical_on_1_2_3_ranks() {
    assert_identical("sphere.toml");
}

#[test]
fn no_particle_is_lost_or_duplicated_by_migration() {
    // Sample every step: the run counts every particle in the gathered profile at each sample
    // and stops with an error if the total changes.
    let dir = tmpdir();
    let every = format!(
        "output.sample_every={}",
        0.5 * 0.005 / (2.0 * std::f64::consts::PI)
    );
    let s = run_on(
        3,
        "periodic.toml",
        dir.path(),
        &["--set", &every, "--set", "run.rotations=0.4"],
    );
    let n = s.id.len() as u64;
    assert!(s.migrations > 20, "only {} migrations", s.migrations);
    assert!(s.rotations.len() > 1000, "{} samples", s.rotations.len());
    let ns_nz = s.count.len() / s.rotations.len();
    for (t, sample) in s.count.chunks_exact(ns_nz).enumerate() {
        assert_eq!(sample.iter().sum::<u64>(), n, "sample {t}");
    }
    assert_eq!(s.id, (0..n).collect::<Vec<_>>());
}

#[test]
fn result_does_not_depend_on_the_skin() {
    // The skin only decides how often lists are rebuilt; a complete list gives the same
    // contacts in the same order, so the states must agree bit for bit.
    let dir = tmpdir();
    let thin = run_on(2, "capped.toml", dir.path(), &["--set", "run.skin=0.25"]);
    let d2 = tmpdir();
    let thick = run_on(2, "capped.toml", d2.path(), &["--set", "run.skin=0.8"]);
    assert_eq!(bits(&thin.position), bits(&thick.position));
    assert_eq!(bits(&thin.velocity), bits(&thick.velocity));
    assert_eq!(bits(&thin.angular_velocity), bits(&thick.angular_velocity));
}

#[test]
fn lifter_drum_is_bit_identical_on_1_2_3_4_ranks() {
    // Lifters turning with the drum, their contacts and histories carried across slab faces;
    // the drum lengthened so that four slabs fit.
    let dir = tmpdir();
    let extra = ["--set", "drum.length=0.04"];
    assert_histories_migrated(&assert_identical_with(
        "lifters.toml",
        &[2, 3, 4],
        &extra,
        &dir,
    ));
}

#[test]
fn cone_drum_is_bit_identical_on_1_2_3_4_ranks() {
    let dir = tmpdir();
    assert_histories_migrated(&assert_identical_with("cone.toml", &[2, 3, 4], &[], &dir));
}

#[test]
fn lifter_and_cone_drums_restart_bit_identically_on_other_rank_counts() {
    // The lifters' angle comes back from the checkpoint's step: a run stopped at 0.047
    // rotations on 2 ranks and continued on 3 ends with the bits of one never interrupted.
    for (case, extra) in [
        ("lifters.toml", "drum.length=0.04"),
        ("cone.toml", "seed=17"),
    ] {
        let dir = tmpdir();
        let d = dir.path();
        let full = run_on(1, case, d, &["--set", extra, "--set", "run.rotations=0.1"]);
        let part = d.join(format!("{case}.2.h5"));
        run_on(
            2,
            case,
            d,
            &["--set", extra, "--set", "run.rotations=0.047"],
        );
        let ck = d.join(format!("{case}.2.ckpt.h5"));
        let case_file = case_path(case);
        let o = mpirun(
            3,
            &[
                "run",
                case_file.to_str().unwrap(),
                "-o",
                part.to_str().unwrap(),
                "--set",
                extra,
                "--set",
                "run.rotations=0.1",
                "--restart",
                ck.to_str().unwrap(),
            ],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let restarted = read(&part);
        assert_eq!(full.id, restarted.id, "{case}: ids");
        for (name, a, b) in [
            ("position", &full.position, &restarted.position),
            ("velocity", &full.velocity, &restarted.velocity),
            (
                "angular_velocity",
                &full.angular_velocity,
                &restarted.angular_velocity,
            ),
        ] {
            assert_eq!(bits(a), bits(b), "{case}: {name} after the restart");
        }
    }
}

#[test]
fn the_spatial_sort_changes_the_order_of_the_sums_and_is_checkpointed() {
    // The test cases sort every 97 steps: the same run never sorted adds its pair forces in
    // the order of the ids, so it must end in other bits (else the sort would not act), and
    // the checkpoints hold the keys of the last sort (all 0 without one).
    let dir = tmpdir();
    let short = ["--set", "run.rotations=0.3"];
    let sorted = run_on(2, "capped.toml", dir.path(), &short);
    let d2 = tmpdir();
    let unsorted = run_on(
        2,
        "capped.toml",
        d2.path(),
        &[short[0], short[1], "--set", "run.sort_every=0"],
    );
    assert_eq!(sorted.id, unsorted.id);
    assert_ne!(bits(&sorted.position), bits(&unsorted.position));
    let keys = |d: &Path| -> Vec<u64> {
        let f = hdf5::File::open(d.join("capped.toml.2.ckpt.h5")).unwrap();
        f.dataset("particles/order_key")
            .unwrap()
            .read_raw()
            .unwrap()
    };
    let mut k = keys(dir.path());
    assert_eq!(k.len(), sorted.id.len());
    k.sort_unstable();
    k.dedup();
    assert!(
        k.len() > sorted.id.len() / 20,
        "only {} distinct keys for {} particles",
        k.len(),
        sorted.id.len()
    );
    assert!(keys(d2.path()).iter().all(|&k| k == 0));
}
