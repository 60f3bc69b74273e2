//! The case loader under random input: every key of the test cases (and the optional keys
//! they leave out) overridden with finite, non-finite, huge, tiny, negative, zero and
//! wrongly typed values, one to three at a time. The loader and validator (in-process) and
//! `tumbler check` (a handful, through the binary) must never panic: a case is accepted or
//! refused with a message, and the binary exits 0 or 2.

mod common;

use common::{case_path, tumbler};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, RngSeed, TestRng, TestRunner};
use toml_edit::{DocumentMut, Item};

const BASES: [&str; 5] = [
    "periodic.toml",
    "capped.toml",
    "sd_capped.toml",
    "sphere.toml",
    "rough.toml",
];

/// Keys a case may hold but the test cases leave out.
const OPTIONAL: [&str; 34] = [
    "drum.shape",
    "drum.length",
    "drum.ends",
    "drum.cap_low",
    "drum.rough_wall.diameter",
    "model.gamma_n",
    "model.collision_time",
    "model.restitution",
    "model.stiffness_ratio",
    "model.gamma_s",
    "model.youngs_modulus",
    "model.poisson_ratio",
    "model.hertz_damping",
    "model.mu_max",
    "model.wall_diameter",
    "species.0.mu_cap",
    "species.0.volume_fraction",
    "species.0.diameter_sd",
    "species.0.restitution",
    "species.0.restitution_wall",
    "species.0.youngs_modulus",
    "species.0.poisson_ratio",
    "init.grow_time",
    "init.settle_time",
    "init.bands",
    "init.file",
    "run.skin",
    "run.dt",
    "output.slice_width",
    "output.checkpoint_every",
    "diagnostics.surface_angle",
    "diagnostics.bands.min_width",
    "diagnostics.paths.every",
    "diagnostics.snapshots.every",
];

/// Values that break things: non-finite, extreme, signed zero, wrong types.
const NASTY: [&str; 28] = [
    "nan",
    "inf",
    "-inf",
    "0",
    "0.0",
    "-0.0",
    "-1.0",
    "-1",
    "1e300",
    "-1e300",
    "1e-300",
    "5e-324",
    "1.7976931348623157e308",
    "18446744073709551615",
    "-9223372036854775808",
    "4294967296",
    "1e9",
    "255",
    "256",
    "\"text\"",
    "\"\"",
    "true",
    "[]",
    "[1.0, 2.0]",
    "[nan, 0.0, 0.0]",
    "{}",
    "{ diameter = 0.0 }",
    "1979-05-27",
];

fn leaf_keys(prefix: &str, item: &Item, out: &mut Vec<String>) {
    match item {
        Item::Table(t) => {
            for (k, v) in t.iter() {
                let key = if prefix.is_empty() {
                    k.to_string()
                } else {
                    format!("{prefix}.{k}")
                };
                leaf_keys(&key, v, out);
            }
        }
        Item::ArrayOfTables(a) => {
            for (i, t) in a.iter().enumerate() {
                for (k, v) in t.iter() {
                    leaf_keys(&format!("{prefix}.{i}.{k}"), v, out);
                }
            }
        }
        Item::Value(_) => out.push(prefix.to_string()),
        Item::None => {}
    }
}

/// Every key of the base case and the optional ones.
fn keys_of(text: &str) -> Vec<String> {
    let doc: DocumentMut = text.parse().unwrap();
    let mut keys = Vec::new();
    leaf_keys("", doc.as_item(), &mut keys);
    keys.extend(OPTIONAL.iter().map(|k| k.to_string()));
    keys.sort();
    keys.dedup();
    keys
}

fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => proptest::sample::select(NASTY.to_vec()).prop_map(str::to_string),
        2 => any::<f64>().prop_map(|x| format!("{x:e}")),
        1 => (-1e3f64..1e3).prop_map(|x| format!("{x:?}")),
        1 => any::<i64>().prop_map(|x| x.to_string()),
    ]
}

/// (base, overrides) drawn from the bases' keys.
fn overrides() -> impl Strategy<Value = (usize, Vec<(usize, String)>)> {
    (
        0..BASES.len(),
        proptest::collection::vec((any::<usize>(), value()), 1..4),
    )
}

fn materialize(
    bases: &[(String, Vec<String>)],
    (b, ov): &(usize, Vec<(usize, String)>),
) -> (usize, Vec<String>) {
    let keys = &bases[*b].1;
    (
        *b,
        ov.iter()
            .map(|(k, v)| format!("{}={v}", keys[k % keys.len()]))
            .collect(),
    )
}

fn runner(cases: u32) -> TestRunner {
    // a fixed seed: the same cases on every run, so that CI is reproducible
    let config = Config {
        cases,
        failure_persistence: None,
        rng_algorithm: RngAlgorithm::ChaCha,
        rng_seed: RngSeed::Fixed(28),
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha))
}

fn bases() -> Vec<(String, Vec<String>)> {
    BASES
        .iter()
        .map(|b| {
            let text = std::fs::read_to_string(case_path(b)).unwrap();
            let keys = keys_of(&text);
            (text, keys)
        })
        .collect()
}

#[test]
fn random_overrides_of_every_key_are_accepted_or_refused_never_a_panic() {
    let bases = bases();
    let (accepted, refused) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
    runner(3000)
        .run(&overrides(), |draw| {
            let (b, ov) = materialize(&bases, &draw);
            match tumbler::case::load_text(&bases[b].0, &ov, BASES[b]) {
                Ok(lc) => {
                    accepted.set(accepted.get() + 1);
                    // what `tumbler check` derives, where the initial state is small
                    if tumbler::case::estimated_particles(&lc.case) < 2e4 {
                        let _ = tumbler::report::check_report(&lc.case, 2);
                    }
                }
                Err(errs) => {
                    refused.set(refused.get() + 1);
                    prop_assert!(!errs.is_empty());
                    for e in &errs {
                        prop_assert!(!e.key.is_empty() && !e.why.is_empty(), "{e:?}");
                    }
                }
            }
            Ok(())
        })
        .unwrap();
    let (accepted, refused) = (accepted.get(), refused.get());
    println!("{accepted} accepted, {refused} refused");
    assert!(
        refused > 0 && accepted > 0,
        "{accepted} accepted, {refused} refused"
    );
}

#[test]
fn tumbler_check_exits_0_or_2_under_random_overrides() {
    let bases = bases();
    runner(12)
        .run(&overrides(), |draw| {
            let (b, ov) = materialize(&bases, &draw);
            let case = case_path(BASES[b]);
            let mut args = vec!["check".to_string(), case.display().to_string()];
            for o in &ov {
                args.push("--set".into());
                args.push(o.clone());
            }
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let out = tumbler(&args);
            let stderr = String::from_utf8_lossy(&out.stderr);
            prop_assert!(
                matches!(out.status.code(), Some(0) | Some(2)),
                "{args:?}: exit {:?}\n{stderr}",
                out.status.code()
            );
            prop_assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
            if out.status.code() == Some(2) {
                prop_assert!(stderr.contains("error"), "{args:?}: {stderr}");
            }
            Ok(())
        })
        .unwrap();
}
