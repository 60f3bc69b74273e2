//! The fcc lattice fill of Rapaport section IV: sites of number density `rho` filling the
//! drum, diameters uniform in `[d - spread, d]`, random velocity directions, species mixed at
//! random in equal numbers or laid out in alternating bands.
//!
//! In a segregated start each band's lattice is scaled by its species' diameter relative to
//! the smallest one (so the big bands hold fewer particles, as in Table I's #V-#Y counts).
//! Ids are in lattice order (layers along the axis, rows, sites). Each rank makes only the
//! layers of its own slab: a site's random draws are keyed by the case's seed and its id
//! ([`super::keyed`]), so the state is the same bits whatever the rank count.

use super::keyed::{self, Permutation, Purpose};
use super::Share;
use crate::case::{Arrangement, Case, Ends};
use crate::particles::ParticleState;
use rand::Rng;

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

/// The initial particles of `case` in `share`, sorted by id.
pub fn lattice(case: &Case, share: &Share) -> Vec<ParticleState> {
    let l = case.drum.axial_length();
    // inside the lifters' tips, if any
    let radius = crate::physics::DrumWalls::of(&case.drum).clear_radius();
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

    // Sites: fcc = simple cubic of step a/2 with (i + j + layer) even. Every layer of a
    // region holds one of two patterns (by parity), so the index of a layer's first site
    // follows from counts alone, without making the sites before it.
    let r_max = radius - gap;
    let mut layers: Vec<Layer> = Vec::new();
    let mut next = 0u64;
    let mut parity = 0usize;
    for (r, reg) in regions.iter().enumerate() {
        let h = 0.5 * reg.spacing;
        let mut n_layers = (((reg.z1 - reg.z0) / h).floor() as usize).max(1);
        if !capped && nb == 1 && n_layers % 2 == 1 && n_layers > 1 {
            n_layers -= 1; // keep the layer parity alternating across the periodic ends
        }
        let dz = (reg.z1 - reg.z0) / n_layers as f64;
        let counts = [0, 1].map(|p| layer_sites(h, r_max, p).count() as u64);
        for k in 0..n_layers {
            layers.push(Layer {
                z: reg.z0 + (k as f64 + 0.5) * dz,
                region: r,
                parity: parity % 2,
                first: next,
            });
            next += counts[parity % 2];
            parity += 1;
        }
    }
    let n = next;

    // Equal numbers of each species, in random order, where mixed.
    let dealt = Permutation::new(n.max(1), case.seed, Purpose::Species, 0);
    let mut out = Vec::new();
    for layer in layers.iter().filter(|l| share.owns(l.z)) {
        let reg = &regions[layer.region];
        for (s, (x, y)) in layer_sites(0.5 * reg.spacing, r_max, layer.parity).enumerate() {
            let id = layer.first + s as u64;
            let species = reg
                .species
                .unwrap_or_else(|| (dealt.apply(id) as u128 * nspecies as u128 / n as u128) as u8);
            let sp = &case.species[species as usize];
            let mut rng = keyed::stream(case.seed, Purpose::Particle, id);
            let diameter = sp.diameter - sp.diameter_spread * rng.gen::<f64>();
            let cos_t: f64 = 2.0 * rng.gen::<f64>() - 1.0;
            let phi = 2.0 * std::f64::consts::PI * rng.gen::<f64>();
            let sin_t = (1.0 - cos_t * cos_t).sqrt();
            let s = case.init.speed;
            let v = [s * sin_t * phi.cos(), s * sin_t * phi.sin(), s * cos_t];
            out.push(ParticleState::new(
                id,
                species,
                diameter,
                [x, y, layer.z],
                v,
                [0.0; 3],
            ));
        }
    }
    out
}

/// One layer of lattice sites.
struct Layer {
    z: f64,
    region: usize,
    /// Which of the two fcc patterns it holds.
    parity: usize,
    /// Global index (id) of its first site.
    first: u64,
}

/// The `(x, y)` of the sites of a layer of parity `parity` on the square grid of step `h`
/// inside radius `r_max`, in the lattice's order (rows along `y`, then `x`).
fn layer_sites(h: f64, r_max: f64, parity: usize) -> impl Iterator<Item = (f64, f64)> {
    let m = (r_max / h).floor() as i64;
    (-m..=m).flat_map(move |j| {
        (-m..=m).filter_map(move |i| {
            if (i + j + parity as i64).rem_euclid(2) != 0 {
                return None;
            }
            let (x, y) = (i as f64 * h, j as f64 * h);
            (x * x + y * y <= r_max * r_max).then_some((x, y))
        })
    })
}
