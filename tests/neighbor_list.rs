//! The neighbour build lists exactly the pairs a search of all pairs finds, in the canonical
//! order (by the ranks `(key, id)` of the two particles, lower first), oriented by id, on
//! every instruction set this CPU has: owned particles and ghosts, particles fixed to the
//! wall, periodic images, mixed sizes, shared order keys, fine and coarse cells.

mod common;

use common::case_with;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumbler::engine::forces::Isa;
use tumbler::engine::neighbor::{
    rank_of, sort_saved, Grid, NeighborList, SavedContact, SavedHistory, SPAN,
};
use tumbler::particles::{ParticleState, Particles};
use tumbler::physics::contact::History;
use tumbler::physics::rough_wall::{is_fixed, FIXED_SPECIES};
use tumbler::physics::{ContactLaw, Materials};

/// `owned` particles in a box of side `side`, then `ghosts` more beyond them (some shifted
/// by a periodic image of `side` along z), diameters 0.5-2 `d`, one in 13 fixed to the wall,
/// order keys from a few values (so that ties fall to the ids), ids shuffled.
fn bed(owned: usize, ghosts: usize, d: f64, side: f64, mat: &Materials, seed: u64) -> Particles {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut ids: Vec<u64> = (0..(owned + ghosts) as u64).map(|i| 3 * i + 7).collect();
    for k in (1..ids.len()).rev() {
        ids.swap(k, rng.gen_range(0..=k));
    }
    let mut p = Particles::default();
    for (k, &id) in ids.iter().enumerate() {
        let ghost = k >= owned;
        let x = [
            rng.gen_range(0.0..side),
            rng.gen_range(0.0..side),
            if ghost {
                rng.gen_range(side..side + 3.0 * d)
            } else {
                rng.gen_range(0.0..side)
            },
        ];
        let species = if k % 13 == 5 {
            FIXED_SPECIES
        } else {
            (k % 2) as u8
        };
        let mut s = ParticleState::new(
            id,
            species,
            d * rng.gen_range(0.5..2.0),
            x,
            [0.0; 3],
            [0.0; 3],
        );
        s.key = rng.gen_range(0..6);
        if ghost {
            // a periodic image: stored a period away, binned where it is seen
            let image = if rng.gen_bool(0.3) { side } else { 0.0 };
            s.x[2] -= image;
            p.push(&s, mat, image);
        } else {
            p.push_owned(&s, mat);
        }
    }
    p
}

/// The list a search of all pairs gives: pairs closer than their halves of the law's cutoff
/// plus `skin`, at least one owned, not both fixed, oriented by id, in canonical order.
fn all_pairs(p: &Particles, law: &ContactLaw, skin: f64) -> Vec<(u32, u32)> {
    let half = |i: usize| 0.5 * law.cutoff(p.diameter[i], p.diameter[i]);
    let at = |i: usize| [p.x[i][0], p.x[i][1], p.x[i][2] + p.z_image[i]];
    let rank = |i: usize| rank_of(p.key[i], p.id[i]);
    let mut found = Vec::new();
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let (xi, xj) = (at(i), at(j));
            let (dx, dy, dz) = (xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]);
            // the build adds the lower-ranked particle's half first
            let (lo, hi) = if rank(i) < rank(j) { (i, j) } else { (j, i) };
            let reach = half(lo) + half(hi) + skin;
            let close = dx * dx + dy * dy + dz * dz < reach * reach;
            let owned = i < p.n_owned || j < p.n_owned;
            let both_fixed = is_fixed(p.species[i]) && is_fixed(p.species[j]);
            if close && owned && !both_fixed {
                let (a, b) = if p.id[i] < p.id[j] { (i, j) } else { (j, i) };
                found.push((a as u32, b as u32));
            }
        }
    }
    found.sort_by_key(|&(a, b)| {
        let (ra, rb) = (rank(a as usize), rank(b as usize));
        (ra.min(rb), ra.max(rb))
    });
    found
}

fn check(law: &ContactLaw, mat: &Materials, d: f64, seed: u64) {
    let side = 10.0 * d;
    let p = bed(1200, 300, d, side, mat, seed);
    let skin = 0.3 * d;
    let reach = law.cutoff(2.0 * d, 2.0 * d) + skin;
    let expected = all_pairs(&p, law, skin);
    assert!(expected.len() > 2000, "only {} pairs", expected.len());
    let (lo, hi) = ([-d, -d, -d], [side + d, side + d, side + 4.0 * d]);
    for grid in [
        Grid::around(&p, reach / SPAN as f64, lo, hi),
        Grid::over(lo, hi, reach),
    ] {
        for isa in [Isa::Reference, Isa::Base, Isa::Avx2, Isa::Avx512] {
            if isa > Isa::of_cpu() {
                continue;
            }
            let mut nl = NeighborList::default();
            nl.build_with(isa, &p, &grid, skin, law);
            assert_eq!(nl.pairs, expected, "{isa:?}, grid {:?}", grid.n);
            let cut2: Vec<f64> = expected
                .iter()
                .map(|&(a, b)| {
                    let c = law.cutoff(p.diameter[a as usize], p.diameter[b as usize]);
                    c * c
                })
                .collect();
            assert_eq!(nl.cut2, cut2, "{isa:?}");
        }
    }
}

#[test]
fn build_lists_all_close_pairs_in_canonical_order() {
    let c = case_with("capped.toml", &[]);
    let (mat, law) = (Materials::new(&c), ContactLaw::new(&c));
    let d = c.species[0].diameter;
    for seed in 1..4 {
        check(&law, &mat, d, seed);
    }
}

#[test]
fn build_with_a_longer_range_law() {
    // Rapaport's law reaches beyond contact (2^(1/6) of the diameter): the search must use
    // its cutoff
    let c = case_with("periodic.toml", &[]);
    let (mat, law) = (Materials::new(&c), ContactLaw::new(&c));
    let d = c.species[0].diameter;
    assert!(
        law.cutoff(d, d) > d,
        "the case's law reaches no further than contact"
    );
    check(&law, &mat, d, 11);
}

#[test]
fn histories_attached_to_a_list_are_saved_back_in_its_order() {
    let c = case_with("cone.toml", &[]);
    let (mat, law) = (Materials::new(&c), ContactLaw::new(&c));
    let words = law.history_words();
    assert!(words > 0, "the case's law keeps no history");
    let d = c.species[0].diameter;
    let side = 10.0 * d;
    let p = bed(1200, 300, d, side, &mat, 5);
    let skin = 0.3 * d;
    let (lo, hi) = ([-d, -d, -d], [side + d, side + d, side + 4.0 * d]);
    let mut nl = NeighborList::default();
    nl.build(
        &p,
        &Grid::over(lo, hi, law.cutoff(2.0 * d, 2.0 * d) + skin),
        skin,
        &law,
    );
    // every third listed pair is a contact in force, with a history of its own
    let mut given: SavedHistory = nl
        .pairs
        .iter()
        .enumerate()
        .filter(|(k, _)| k % 3 == 0)
        .map(|(k, &(a, b))| {
            let (a, b) = (a as usize, b as usize);
            let mut h = History::default();
            for (w, x) in h[..words].iter_mut().enumerate() {
                *x = (10 * k + w + 1) as f64 * 1e-7;
            }
            SavedContact {
                a: p.id[a],
                b: p.id[b],
                key_a: p.key[a],
                key_b: p.key[b],
                h,
            }
        })
        .collect();
    assert!(given.len() > 500, "only {} contacts", given.len());
    sort_saved(&mut given);
    nl.attach_histories(&p, &given);
    assert_eq!(nl.save_histories(&p), given);
}
