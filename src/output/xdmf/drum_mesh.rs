//! The drum's wall as a coarse triangle mesh in the lab frame, for the `.xmf` file and
//! `tumbler export --vtu`: a cylinder along `z` with its end caps (none for periodic
//! ends), or a sphere.

use crate::case::Shape;

/// Segments around the drum's circumference in its surface mesh.
pub const DRUM_SEGMENTS: usize = 48;
/// Rings from pole to pole of a spherical drum's surface mesh.
pub const SPHERE_RINGS: usize = 24;

/// The drum's wall as `(points, triangles)` in the lab frame.
pub fn drum_mesh(shape: Shape, diameter: f64, length: f64, periodic: bool) -> DrumMesh {
    let r = 0.5 * diameter;
    let n = DRUM_SEGMENTS;
    let mut pts = Vec::new();
    let mut tri = Vec::new();
    let angle = |k: usize| 2.0 * std::f64::consts::PI * (k % n) as f64 / n as f64;
    match shape {
        Shape::Cylinder => {
            let h = 0.5 * length;
            for z in [-h, h] {
                for k in 0..n {
                    pts.push([r * angle(k).cos(), r * angle(k).sin(), z]);
                }
            }
            for k in 0..n {
                let (a, b) = (k, (k + 1) % n);
                tri.push([a, b, n + b]);
                tri.push([a, n + b, n + a]);
            }
            if !periodic {
                let (lo, hi) = (pts.len(), pts.len() + 1);
                pts.push([0.0, 0.0, -h]);
                pts.push([0.0, 0.0, h]);
                for k in 0..n {
                    let (a, b) = (k, (k + 1) % n);
                    tri.push([lo, b, a]);
                    tri.push([hi, n + a, n + b]);
                }
            }
        }
        Shape::Sphere => {
            let m = SPHERE_RINGS;
            pts.push([0.0, 0.0, -r]);
            for i in 1..m {
                let polar = std::f64::consts::PI * i as f64 / m as f64;
                let (s, c) = (polar.sin(), polar.cos());
                for k in 0..n {
                    pts.push([r * s * angle(k).cos(), r * s * angle(k).sin(), -r * c]);
                }
            }
            pts.push([0.0, 0.0, r]);
            let ring = |i: usize, k: usize| 1 + (i - 1) * n + k % n;
            let top = pts.len() - 1;
            for k in 0..n {
                tri.push([0, ring(1, k + 1), ring(1, k)]);
                tri.push([top, ring(m - 1, k), ring(m - 1, k + 1)]);
            }
            for i in 1..m - 1 {
                for k in 0..n {
                    tri.push([ring(i, k), ring(i, k + 1), ring(i + 1, k + 1)]);
                    tri.push([ring(i, k), ring(i + 1, k + 1), ring(i + 1, k)]);
                }
            }
        }
    }
    DrumMesh {
        points: pts,
        triangles: tri,
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
