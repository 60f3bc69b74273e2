//! The drum's walls: a vessel (the drum body: cylinder, sphere or cone, each with its own
//! surfaces) and optional flat lifters fixed to its curved wall, all turning with the drum
//! about `+z`. The wall moves with `omega z x x_wall` at the contact point.
//!
//! [`DrumWalls`] is the one description of the drum that the rest of the program asks:
//! contacts ([`DrumWalls::load`]), the near-wall test of the list builds
//! ([`DrumWalls::near`]), "inside?" ([`DrumWalls::inside`]: health, explicit particles),
//! the interior volume and the fill below a height (the pour's count and cut, both of the
//! free volume: the vessel's less the lifters'), the placement
//! bounds of the pour and the lattice, and the wall mesh of the outputs.
//!
//! Each vessel is one file implementing [`Vessel`] (`cylinder.rs`, `sphere.rs`, `cone.rs`),
//! made from the case in [`vessel_of`]; its own keys are checked by its `check`, called from
//! [`check`] (which `case::validate` calls). Adding a drum shape is: the vessel's file, its
//! keys in `case/schema.rs`, and its arm in [`vessel_of`] and [`check`] here.

mod cone;
mod cylinder;
mod lifters;
mod sphere;

pub use cone::Cone;
pub use cylinder::Cylinder;
pub use lifters::Lifters;
pub use sphere::Sphere;

use super::contact::Body;
use super::law::ContactLaw;
use super::materials::{Materials, Wall, WALLS};
use super::rapaport::V3;
use crate::case::{Drum, Shape};
use std::sync::Arc;

/// A wall point seen from a particle centre `x`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touch {
    /// From the closest wall point to the centre (its length is the distance).
    pub r: V3,
    /// The closest wall point (lab frame), whose velocity is `omega z x at`.
    pub at: V3,
}

/// The slots of a vessel's surfaces, in the order of the force sum.
pub const VESSEL_SLOTS: [Wall; 3] = [Wall::Curved, Wall::CapLow, Wall::CapHigh];

/// Every wall history slot, in the order of the force sum: the vessel's, then the lifters'.
pub const WALL_SLOTS: [Wall; WALLS] = [Wall::Curved, Wall::CapLow, Wall::CapHigh, Wall::Lifter];

/// The drum body: its surfaces and its interior. Angles do not matter to a vessel (it is a
/// body of revolution about `z`); what turns with the drum is its wall velocity.
pub trait Vessel: std::fmt::Debug + Send + Sync {
    /// The wall points within `reach` of the centre `x`, for the curved wall (or sphere),
    /// the low cap and the high cap ([`VESSEL_SLOTS`]); `None` where out of reach.
    fn contacts(&self, x: V3, reach: f64) -> [Option<Touch>; 3];
    /// Whether `x` is within `reach` of a surface (a superset of where `contacts` finds one).
    fn near(&self, x: [f64; 3], reach: f64) -> bool;
    /// Whether a sphere of radius `margin` centred at `x` is inside the walls (the axial
    /// range of periodic ends is not a wall and is not tested).
    fn inside(&self, x: [f64; 3], margin: f64) -> bool;
    /// Volume inside the walls.
    fn volume(&self) -> f64;
    /// Fraction of the volume below the height `y = h`.
    fn fill_below(&self, h: f64) -> f64;
    /// Largest distance of the wall from the axis.
    fn radius(&self) -> f64;
    /// Axial extent from the centre: `L/2`, or `R` for a sphere.
    fn half_length(&self) -> f64;
    /// Placement of the pour, by cells of side `2 jitter` or more: for the layer of cells
    /// at `z` (their points within `jitter` of it along the axis), how much the square of
    /// the radius at which a centre is `margin` from the wall falls short of `room^2`, where
    /// `room = radius() - margin` (0 for a cylinder).
    fn placement_cut(&self, room: f64, margin: f64, z: f64, jitter: f64) -> f64;
    /// Axial half extent of the pour's layer centres, for points `margin` from the wall
    /// (`room` as in [`Self::placement_cut`]); `d_max` the largest diameter.
    fn placement_half_length(&self, room: f64, d_max: f64) -> f64;
    /// The volume a centre may take (`room` as in [`Self::placement_cut`]).
    fn placement_volume(&self, room: f64, margin: f64) -> f64;
    /// The wall's triangles (lab frame), counter-clockwise seen from inside.
    fn mesh(&self, mesh: &mut DrumMesh);
}

/// The vessel of a (validated) drum.
pub fn vessel_of(drum: &Drum) -> Arc<dyn Vessel> {
    let r = 0.5 * drum.diameter;
    match drum.shape {
        Shape::Cylinder => Arc::new(Cylinder {
            radius: r,
            half_length: 0.5 * drum.length.unwrap_or(0.0),
            capped: !drum.periodic(),
        }),
        Shape::Sphere => Arc::new(Sphere { radius: r }),
        Shape::Cone => Arc::new(Cone::new(
            r,
            0.5 * drum.diameter_high.unwrap_or(drum.diameter),
            0.5 * drum.length.unwrap_or(0.0),
        )),
    }
}

/// Refusals of the drum's shape keys that belong to the vessels and lifters: `(key, why)`.
/// `reach` is the wall reach of the largest particle (how close a particle's centre comes
/// to a wall it touches).
pub fn check(drum: &Drum, reach: f64) -> Vec<(String, String)> {
    let mut out = Vec::new();
    if drum.shape == Shape::Cone {
        cone::check(drum, &mut out);
    } else if drum.diameter_high.is_some() {
        out.push((
            "drum.diameter_high".into(),
            "applies to a cone only (drum.shape = \"cone\")".into(),
        ));
    }
    if let Some(l) = &drum.lifters {
        lifters::check(drum, l, reach, &mut out);
    }
    out
}

/// Geometry and motion of the drum's walls.
#[derive(Debug, Clone)]
pub struct DrumWalls {
    /// The drum body.
    pub vessel: Arc<dyn Vessel>,
    /// Lifters on the curved wall, if any.
    pub lifters: Option<Lifters>,
    /// Largest radius of the wall (the vessel's).
    pub radius: f64,
    /// Axial half extent (caps, if any, at `z = -L/2` and `z = +L/2`).
    pub half_length: f64,
    /// Angular velocity of the drum about `+z`.
    pub omega: f64,
}

/// Force and torque that the walls exert on one particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallLoad {
    /// Total force.
    pub force: V3,
    /// Total torque about the particle centre.
    pub torque: V3,
}

/// The velocity of the wall point `at` of a drum turning at `omega` about `+z`.
#[inline]
pub fn wall_velocity(at: V3, omega: f64) -> V3 {
    V3::new(-at.y, at.x, 0.0) * omega
}

impl DrumWalls {
    /// The walls of a (validated) drum, at angle zero.
    pub fn of(drum: &Drum) -> Self {
        let vessel = vessel_of(drum);
        DrumWalls {
            radius: vessel.radius(),
            half_length: vessel.half_length(),
            lifters: drum.lifters.as_ref().map(|l| Lifters::of(drum, l)),
            vessel,
            omega: drum.omega,
        }
    }

    /// Turn the walls to the drum angle `angle` (the lifters; the vessel is round).
    pub fn turn_to(&mut self, angle: f64) {
        if let Some(l) = &mut self.lifters {
            l.turn_to(angle);
        }
    }

    /// Whether a particle centred at `x` is within `reach` of a wall (where [`Self::load`]
    /// may find a contact for a particle of that reach or less) at any drum angle: the
    /// lifters turn between two list builds.
    pub fn near(&self, x: [f64; 3], reach: f64) -> bool {
        self.vessel.near(x, reach) || self.lifters.as_ref().is_some_and(|l| l.near(x, reach))
    }

    /// Whether a particle of wall reach `reach` centred at `x` touches a wall now.
    pub fn touches(&self, x: [f64; 3], reach: f64) -> bool {
        self.contacts(V3::from(x), reach)
            .iter()
            .any(Option::is_some)
    }

    /// The wall points within `reach` of a particle centred at `x`, one per slot of
    /// [`WALL_SLOTS`] (`None` where out of reach, and for the lifters of a drum without).
    #[inline]
    pub fn contacts(&self, x: V3, reach: f64) -> [Option<Touch>; WALLS] {
        let [curved, low, high] = self.vessel.contacts(x, reach);
        let lifter = self.lifters.as_ref().and_then(|l| l.contact(x, reach));
        [curved, low, high, lifter]
    }

    /// Whether a sphere of radius `margin` at `x` is inside the walls (clear of the lifters
    /// at their present angle).
    pub fn inside(&self, x: [f64; 3], margin: f64) -> bool {
        self.vessel.inside(x, margin) && self.lifters.as_ref().is_none_or(|l| l.clear(x, margin))
    }

    /// Volume inside the walls, less the lifters'.
    pub fn volume(&self) -> f64 {
        self.vessel.volume()
            - self
                .lifters
                .as_ref()
                .map_or(0.0, |l| l.volume_in(2.0 * self.half_length))
    }

    /// Fraction of the free volume ([`Self::volume`]: the vessel's less the lifters') below
    /// the height `y = h`, with the lifters at their present angle: the vessel's volume below
    /// `h` less the lifters' cross-sections below it ([`Lifters::area_below`]) times their
    /// length (the rounded axial ends of a span are not counted, as in the volume).
    pub fn fill_below(&self, h: f64) -> f64 {
        match &self.lifters {
            None => self.vessel.fill_below(h),
            Some(l) => {
                let plates = l.area_below(h) * l.length_in(2.0 * self.half_length);
                (self.vessel.fill_below(h) * self.vessel.volume() - plates) / self.volume()
            }
        }
    }

    /// Height below which the free volume is the fraction `fill` ([`Self::fill_below`]).
    pub fn cut_height(&self, fill: f64) -> f64 {
        let radius = self.radius;
        let (mut lo, mut hi) = (-radius, radius);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.fill_below(mid) < fill {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// Inner radius clear of the lifters (the vessel's largest radius without them): where
    /// the pour and the lattice place centres.
    pub fn clear_radius(&self) -> f64 {
        match &self.lifters {
            Some(l) => self.radius - l.height,
            None => self.radius,
        }
    }

    /// The wall's triangles in the lab frame (lifters at the present angle).
    pub fn mesh(&self) -> DrumMesh {
        let mut m = DrumMesh {
            points: Vec::new(),
            triangles: Vec::new(),
        };
        self.vessel.mesh(&mut m);
        if let Some(l) = &self.lifters {
            l.mesh_in(&mut m, self.half_length);
        }
        m
    }

    /// Sum of the wall forces on a particle at `x` (curved wall or sphere first, then the cap
    /// at `-L/2`, then at `+L/2`, then a lifter), updating its wall histories `hist`
    /// ([`WALLS`] slots of the law's history words, one after the other).
    #[inline]
    pub fn load(
        &self,
        law: &ContactLaw,
        mat: &Materials,
        species: u8,
        x: V3,
        body: &Body,
        hist: &mut [f64],
    ) -> WallLoad {
        let reach = law.wall_reach(body.d);
        let mut out = WallLoad {
            force: V3::zeros(),
            torque: V3::zeros(),
        };
        let words = hist.len() / WALLS;
        let w_wall = V3::new(0.0, 0.0, self.omega);
        let rolling = law.has_rolling();
        let mut touch = |wall: Wall, t: Option<Touch>, hist: &mut [f64]| match t {
            Some(t) => {
                let v_wall = wall_velocity(t.at, self.omega);
                let fr = mat.wall(species, wall);
                if let Some(c) = law.wall(t.r, body, v_wall, w_wall, fr, hist) {
                    out.force += c.force;
                    out.torque -= c.n_cross_fs * (0.5 * body.d);
                    if rolling {
                        out.torque += c.torque_roll;
                    }
                }
            }
            None => hist.fill(0.0),
        };
        let found = self.contacts(x, reach);
        for (k, (wall, t)) in WALL_SLOTS.into_iter().zip(found).enumerate() {
            touch(wall, t, &mut hist[k * words..(k + 1) * words]);
        }
        out
    }
}

/// A triangle mesh of the drum's wall.
#[derive(Debug, Clone)]
pub struct DrumMesh {
    /// Points (lab frame).
    pub points: Vec<[f64; 3]>,
    /// Triangles (indices into `points`), counter-clockwise seen from inside the drum.
    pub triangles: Vec<[usize; 3]>,
}

/// Segments around the drum's circumference in its surface mesh.
pub const DRUM_SEGMENTS: usize = 48;
/// Rings from pole to pole of a spherical drum's surface mesh.
pub const SPHERE_RINGS: usize = 24;

/// Area of the part of a disc of radius `r` centred at the origin below the height `h`.
pub fn segment_area(r: f64, h: f64) -> f64 {
    let h = h.clamp(-r, r);
    h * (r * r - h * h).sqrt() + r * r * (h / r).asin() + 0.5 * std::f64::consts::PI * r * r
}
