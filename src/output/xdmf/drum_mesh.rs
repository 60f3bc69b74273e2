//! The drum's wall as a coarse triangle mesh in the lab frame, for the `.xmf` file and
//! `tumbler export --vtu`: the drum description's own mesh (`physics::walls`): a cylinder
//! along `z` with its end caps (none for periodic ends), a sphere, a cone, and the lifters
//! as boxes at their angle at time zero.

use crate::case::Drum;
pub use crate::physics::walls::{DrumMesh, DRUM_SEGMENTS, SPHERE_RINGS};

/// The drum's wall as `(points, triangles)` in the lab frame, at time zero.
pub fn drum_mesh(drum: &Drum) -> DrumMesh {
    crate::physics::DrumWalls::of(drum).mesh()
}
