//! A rough curved wall made of particles fixed to the turning drum (thesis ch. 3 uses one to
//! stop slip at the wall). Wall particles are spheres centred on the wall surface, in rings
//! one diameter apart along the axis, each ring spaced evenly around, alternate rings turned
//! by half a spacing. Their positions follow from their id and the drum angle alone.
//!
//! In the engine they are particles of species [`FIXED_SPECIES`] with infinite mass: they
//! take part in pair contacts (as a wall does: `m_eff` is the mobile particle's mass), are
//! owned by the slab of their `z`, never migrate, and are left out of diagnostics and output.

use crate::case::Case;
use crate::particles::ParticleState;
use std::f64::consts::PI;

/// Species index of wall particles.
pub const FIXED_SPECIES: u8 = u8::MAX;

/// Ids of wall particles start here (above any mobile id).
pub const FIRST_ID: u64 = 1 << 40;

/// Whether a species index is that of wall particles.
#[inline]
pub fn is_fixed(species: u8) -> bool {
    species == FIXED_SPECIES
}

/// The geometry of a rough wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughWall {
    /// Diameter of the wall particles.
    pub diameter: f64,
    /// Radius of the ring of centres (the drum radius).
    pub radius: f64,
    /// Rings along the axis.
    pub rings: u64,
    /// Particles per ring.
    pub per_ring: u64,
    /// Axial position of the first ring.
    pub z0: f64,
    /// Axial spacing of rings.
    pub dz: f64,
}

impl RoughWall {
    /// The rough wall of `case`, if it has one.
    pub fn of(case: &Case) -> Option<Self> {
        let rw = case.drum.rough_wall.as_ref()?;
        let radius = 0.5 * case.drum.diameter;
        let length = case.drum.axial_length();
        let rings = ((length / rw.diameter).floor() as u64).max(1);
        let dz = length / rings as f64;
        Some(RoughWall {
            diameter: rw.diameter,
            radius,
            rings,
            per_ring: ((2.0 * PI * radius / rw.diameter).floor() as u64).max(1),
            z0: -0.5 * length + 0.5 * dz,
            dz,
        })
    }

    /// Number of wall particles.
    pub fn count(&self) -> u64 {
        self.rings * self.per_ring
    }

    /// Position and velocity of wall particle `id` when the drum has turned by `angle` at
    /// angular velocity `omega`.
    #[inline]
    pub fn place(&self, id: u64, angle: f64, omega: f64) -> ([f64; 3], [f64; 3]) {
        let k = id - FIRST_ID;
        let (ring, j) = (k / self.per_ring, k % self.per_ring);
        let stagger = if ring % 2 == 1 { 0.5 } else { 0.0 };
        let phi = 2.0 * PI * (j as f64 + stagger) / self.per_ring as f64 + angle;
        let (x, y) = (self.radius * phi.cos(), self.radius * phi.sin());
        (
            [x, y, self.z0 + ring as f64 * self.dz],
            [-omega * y, omega * x, 0.0],
        )
    }

    /// All wall particles at drum angle 0.
    pub fn particles(&self, omega: f64) -> Vec<ParticleState> {
        (0..self.count())
            .map(|k| {
                let id = FIRST_ID + k;
                let (x, v) = self.place(id, 0.0, omega);
                ParticleState::new(id, FIXED_SPECIES, self.diameter, x, v, [0.0, 0.0, omega])
            })
            .collect()
    }
}
