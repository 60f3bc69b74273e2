//! The fcc lattice fill of Rapaport section IV: sites of number density `rho` filling the
//! drum, diameters uniform in `[d - spread, d]`, random velocity directions, species mixed at
//! random in equal numbers or laid out in alternating bands.
//!
//! In a segregated start each band's lattice is scaled by its species' diameter relative to
//! the smallest one (so the big bands hold fewer particles, as in Table I's #V-#Y counts).
//! The whole state is made on every rank from the case's seed alone, with ids in lattice order,
//! so it is the same whatever the rank count.

use crate::case::{Arrangement, Case, Ends};
use crate::particles::ParticleState;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// An axial region filled with one lattice.
struct Region {
    z0: f64,
    z1: f64,
    /// Species of a segregated band; `None` when mixed.
    species: Option<u8>,
    spacing: f64,
}

/// Side of the cubic fcc cell of number density `rho` (4 sites per cell).
pub fn fcc_spacing(rho: f64) -> f64 {
    (4.0 / rho).cbrt()
}

/// The initial particles of `case`, sorted by id.
pub fn lattice(case: &Case) -> Vec<ParticleState> {
    let l = case.drum.axial_length();
    let radius = 0.5 * case.drum.diameter;
    let gap = case.init.wall_gap;
    let capped = case.drum.ends == Some(Ends::Capped);
    let a0 = fcc_spacing(case.init.density.unwrap_or(f64::NAN));
    let d_min = case
        .species
        .iter()
        .map(|s| s.diameter)
        .fold(f64::MAX, f64::min);
    let nspecies = case.species.len();

    let nb = match case.init.arrangement {
        Arrangement::Mixed => 1,
        Arrangement::Segregated => case.init.bands,
    };
    let regions: Vec<Region> = (0..nb)
        .map(|k| {
            let mut z0 = -0.5 * l + l * k as f64 / nb as f64;
            let mut z1 = if k + 1 == nb {
                0.5 * l
            } else {
                -0.5 * l + l * (k + 1) as f64 / nb as f64
            };
            if capped && k == 0 {
                z0 += gap;
            }
            if capped && k + 1 == nb {
                z1 -= gap;
            }
            let (species, spacing) = match case.init.arrangement {
                Arrangement::Mixed => (None, a0),
                Arrangement::Segregated => {
                    let s = (k % nspecies) as u8;
                    (Some(s), a0 * case.species[s as usize].diameter / d_min)
                }
            };
            Region {
                z0,
                z1,
                species,
                spacing,
            }
        })
        .collect();

    // Sites: fcc = simple cubic of step a/2 with (i + j + layer) even.
    let mut sites: Vec<([f64; 3], Option<u8>)> = Vec::new();
    let mut layer_parity = 0usize;
    let r_max = radius - gap;
    for reg in &regions {
        let h = 0.5 * reg.spacing;
        let mut n_layers = (((reg.z1 - reg.z0) / h).floor() as usize).max(1);
        if !capped && nb == 1 && n_layers % 2 == 1 && n_layers > 1 {
            n_layers -= 1; // keep the layer parity alternating across the periodic ends
        }
        let dz = (reg.z1 - reg.z0) / n_layers as f64;
        let m = (r_max / h).floor() as i64;
        for k in 0..n_layers {
            let z = reg.z0 + (k as f64 + 0.5) * dz;
            for j in -m..=m {
                for i in -m..=m {
                    if (i + j + layer_parity as i64).rem_euclid(2) != 0 {
                        continue;
                    }
                    let (x, y) = (i as f64 * h, j as f64 * h);
                    if x * x + y * y <= r_max * r_max {
                        sites.push(([x, y, z], reg.species));
                    }
                }
            }
            layer_parity += 1;
        }
    }

    let mut rng = ChaCha8Rng::seed_from_u64(case.seed);
    let n = sites.len();
    // Equal numbers of each species, in random order, where mixed.
    let mut mixed_species: Vec<u8> = (0..n).map(|k| (k * nspecies / n.max(1)) as u8).collect();
    mixed_species.shuffle(&mut rng);

    sites
        .iter()
        .enumerate()
        .map(|(k, &(x, band))| {
            let species = band.unwrap_or(mixed_species[k]);
            let sp = &case.species[species as usize];
            let diameter = sp.diameter - sp.diameter_spread * rng.gen::<f64>();
            let cos_t: f64 = 2.0 * rng.gen::<f64>() - 1.0;
            let phi = 2.0 * std::f64::consts::PI * rng.gen::<f64>();
            let sin_t = (1.0 - cos_t * cos_t).sqrt();
            let s = case.init.speed;
            let v = [s * sin_t * phi.cos(), s * sin_t * phi.sin(), s * cos_t];
            ParticleState::new(k as u64, species, diameter, x, v, [0.0; 3])
        })
        .collect()
}
