//! Initial states: Rapaport's fcc lattice, the thesis' pour fill, explicit particles.
//!
//! Each rank makes only the particles of its own [`Share`] of the drum. Every random draw is
//! keyed by the case's seed and a global index ([`keyed`]), never taken from one sequential
//! stream, so the particles a rank makes are the same bits whichever ranks make the others.

mod explicit;
pub mod keyed;
mod lattice;
pub mod pour;

pub use explicit::{duplicate, duplicate_id, explicit};
pub use lattice::{fcc_spacing, lattice};

use crate::case::{Case, InitKind};
use crate::particles::ParticleState;

/// The axial part of the drum whose particles one rank makes: `owns(z)` decides, exactly as
/// the slabs decide who owns a particle; `[lo, hi]` bounds that part, so that whole layers
/// and blocks outside it are skipped.
pub struct Share<'a> {
    /// Lowest `z` owned.
    pub lo: f64,
    /// Highest `z` owned.
    pub hi: f64,
    owns: &'a dyn Fn(f64) -> bool,
}

impl<'a> Share<'a> {
    /// The part `[lo, hi]` in which `owns` holds.
    pub fn new(lo: f64, hi: f64, owns: &'a dyn Fn(f64) -> bool) -> Self {
        Share { lo, hi, owns }
    }

    /// The whole drum.
    pub fn everything() -> Share<'static> {
        Share {
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
            owns: &|_| true,
        }
    }

    /// Whether a particle at axial position `z` is made here.
    pub fn owns(&self, z: f64) -> bool {
        (self.owns)(z)
    }

    /// Whether anything in `[z0, z1]` may be made here.
    pub fn meets(&self, z0: f64, z1: f64) -> bool {
        z1 >= self.lo && z0 <= self.hi
    }
}

/// The particles a run starts from in `share`, sorted by id, and the factor by which their
/// diameters start (below 1 only for a pour, whose points then grow and settle in the engine).
pub fn initial_particles(case: &Case, share: &Share) -> Result<(Vec<ParticleState>, f64), String> {
    match case.init.kind {
        InitKind::Lattice => Ok((lattice(case, share), 1.0)),
        InitKind::Particles => Ok((explicit(case, share)?, 1.0)),
        InitKind::Pour => pour::points(case, share),
    }
}

/// Particles made at a time by [`count_by_species`].
const COUNT_PART: f64 = 1e6;

/// How many particles of each species the initial state of `case` holds (before a pour's
/// cut), made part by part along the axis so that no more than about a million are held at
/// once (a particle file is read whole: its parts are what the ranks read).
pub fn count_by_species(case: &Case) -> Result<Vec<u64>, String> {
    let parts = match case.init.kind {
        InitKind::Particles => 1,
        _ => (crate::case::estimated_particles(case) / COUNT_PART)
            .ceil()
            .clamp(1.0, 1e6) as usize,
    };
    let slabs = crate::engine::Slabs::uniform(parts, case.drum.axial_length(), false);
    let mut counts = vec![0u64; case.species.len()];
    for k in 0..parts {
        let owns = |z: f64| slabs.owner(z) == k;
        let (lo, hi) = slabs.owned_span(k);
        for p in initial_particles(case, &Share::new(lo, hi, &owns))?.0 {
            counts[p.species as usize] += 1;
        }
    }
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::parse_case;
    use crate::engine::sim::initial_slabs;

    fn case(name: &str, overrides: &str) -> Case {
        let text = crate::validate::case_text(name).unwrap().to_string() + overrides;
        parse_case(&text, name).unwrap_or_else(|e| panic!("{e:?}"))
    }

    /// The parts that 2, 3, 5 and 8 ranks make of the initial state are, put together, the
    /// whole state made at once, bit for bit; each part is only its own slab's particles.
    fn parts_make_the_whole(case: &Case) {
        let (whole, scale) = initial_particles(case, &Share::everything()).unwrap();
        assert!(whole.len() > 1000, "{} particles", whole.len());
        assert!(whole.iter().enumerate().all(|(k, p)| p.id == k as u64));
        let key = |ps: &[ParticleState]| format!("{ps:?}");
        for ranks in [2, 3, 5, 8] {
            let slabs = initial_slabs(case, ranks);
            let mut all = Vec::new();
            for r in 0..ranks {
                let owns = |z: f64| slabs.owner(z) == r;
                let (lo, hi) = slabs.owned_span(r);
                let (part, s) = initial_particles(case, &Share::new(lo, hi, &owns)).unwrap();
                assert_eq!(s.to_bits(), scale.to_bits());
                assert!(part.iter().all(|p| slabs.owner(p.x[2]) == r));
                assert!(part.windows(2).all(|w| w[0].id < w[1].id));
                all.extend(part);
            }
            all.sort_by_key(|p| p.id);
            assert!(key(&all) == key(&whole), "{ranks} ranks make another state");
        }
    }

    #[test]
    fn counts_made_in_parts_are_those_of_the_whole() {
        for c in [
            case("rapaport2002-A", ""),
            case("chen2008-ch4-endwalls", ""),
        ] {
            let (whole, _) = initial_particles(&c, &Share::everything()).unwrap();
            let mut counts = vec![0u64; c.species.len()];
            for p in &whole {
                counts[p.species as usize] += 1;
            }
            assert_eq!(count_by_species(&c).unwrap(), counts);
        }
    }

    #[test]
    fn lattice_parts_make_the_whole() {
        // mixed (species dealt out at random), and segregated in bands
        parts_make_the_whole(&case("rapaport2002-A", ""));
        parts_make_the_whole(&case("rapaport2002-V", ""));
    }

    #[test]
    fn pour_parts_make_the_whole() {
        parts_make_the_whole(&case("chen2008-ch4-periodic-w3.14", ""));
        parts_make_the_whole(&case("chen2008-ch5-sphere-fill20", ""));
        parts_make_the_whole(&case("chen2008-ch4-endwalls", ""));
    }

    #[test]
    fn pour_deals_out_the_species_by_volume() {
        let c = case("chen2008-ch4-periodic-w3.14", "");
        let (points, scale) = initial_particles(&c, &Share::everything()).unwrap();
        assert!(scale > 0.2 && scale < 0.9, "scale {scale}");
        let volume = |s: u8| -> f64 {
            points
                .iter()
                .filter(|p| p.species == s)
                .map(|p| p.diameter.powi(3))
                .sum()
        };
        let share = volume(0) / (volume(0) + volume(1));
        let wanted = c.species[0].volume_fraction.unwrap();
        assert!((share - wanted).abs() < 0.02, "{share} against {wanted}");
        // spread evenly along the axis: each fifth of the drum holds a fifth of the points
        let l = c.drum.axial_length();
        for k in 0..5 {
            let lo = -0.5 * l + 0.2 * l * k as f64;
            let n = points
                .iter()
                .filter(|p| (lo..lo + 0.2 * l).contains(&p.x[2]))
                .count() as f64;
            let frac = n / points.len() as f64;
            assert!((frac - 0.2).abs() < 0.01, "fifth {k}: {frac}");
        }
    }
}
