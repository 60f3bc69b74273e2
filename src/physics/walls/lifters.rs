//! Flat lifters (flights, baffles) fixed to a cylinder's curved wall along the axis, turning
//! with the drum: `count` plates equally spaced in angle, each reaching `height` in from the
//! wall, `thickness` thick, along the whole drum or an axial span.
//!
//! A lifter is the solid within `thickness/2` of its mid-rectangle (a rectangle with rounded
//! edges): in the frame of lifter `k` (radial `u`, tangential `w`, axial `z`) the rectangle
//! is `w = 0`, `R - height + thickness/2 <= u <= R`, `z` in the span, so that the lifter's
//! innermost point is at `R - height`. The closest point of the solid to a centre is the
//! closest point `c` of the rectangle moved `thickness/2` towards the centre.
//!
//! All lifters share one history slot per particle (`Wall::Lifter`), with the curved wall's
//! friction: a particle touches at most one lifter at a time, because the case check
//! ([`check`]) refuses lifters whose tips are closer to each other than twice the wall reach
//! of the largest particle. Each contact is tested against the nearest lifter only.

use super::{DrumMesh, Touch};
use crate::case::{Drum, DrumLifters, Shape};
use crate::physics::rapaport::V3;
use std::f64::consts::PI;

/// The lifters of a drum and their present angle.
#[derive(Debug, Clone)]
pub struct Lifters {
    /// How many, equally spaced in angle.
    pub count: usize,
    /// Radial height from the wall to the innermost point.
    pub height: f64,
    /// Thickness (the diameter of the rounded edges).
    pub thickness: f64,
    /// Radius of the curved wall (the lifters' root).
    pub radius: f64,
    /// Radial position of the tip's mid-line, `R - height + thickness/2`.
    pub tip: f64,
    /// Axial span, or `None` for the whole drum.
    pub span: Option<[f64; 2]>,
    /// Angle of lifter 0 at time zero, from `+x` towards `+y`.
    pub phase: f64,
    /// `(cos, sin)` of each lifter's angle at the present drum angle.
    dirs: Vec<(f64, f64)>,
}

/// The nearest point of a lifter's mid-rectangle: `(k, u, w, z - z_c, u - u_c, distance^2)`.
type Nearest = (usize, f64, f64, f64, f64, f64);

impl Lifters {
    /// The lifters of a (validated) drum, at drum angle zero.
    pub fn of(drum: &Drum, l: &DrumLifters) -> Self {
        let radius = 0.5 * drum.diameter;
        let mut out = Lifters {
            count: l.count as usize,
            height: l.height,
            thickness: l.thickness,
            radius,
            tip: radius - l.height + 0.5 * l.thickness,
            span: l.span,
            phase: l.angle,
            dirs: Vec::new(),
        };
        out.turn_to(0.0);
        out
    }

    /// Turn the lifters to the drum angle `angle`.
    pub fn turn_to(&mut self, angle: f64) {
        let n = self.count;
        self.dirs = (0..n)
            .map(|k| {
                let (s, c) = (self.phase + angle + 2.0 * PI * k as f64 / n as f64).sin_cos();
                (c, s)
            })
            .collect();
    }

    /// `(cos, sin)` of each lifter's present angle.
    pub fn directions(&self) -> &[(f64, f64)] {
        &self.dirs
    }

    /// The nearest lifter's mid-rectangle to `x` (the first of equals).
    fn nearest(&self, x: [f64; 3]) -> Nearest {
        let dz = match self.span {
            Some([lo, hi]) => x[2] - x[2].clamp(lo, hi),
            None => 0.0,
        };
        let mut best: Nearest = (0, 0.0, 0.0, 0.0, 0.0, f64::INFINITY);
        for (k, &(c, s)) in self.dirs.iter().enumerate() {
            let u = x[0] * c + x[1] * s;
            let w = x[1] * c - x[0] * s;
            let du = u - u.clamp(self.tip, self.radius);
            let d2 = du * du + w * w + dz * dz;
            if d2 < best.5 {
                best = (k, u, w, dz, du, d2);
            }
        }
        best
    }

    /// The closest point of the nearest lifter to the centre `x`, if within `reach` of it.
    pub fn contact(&self, x: V3, reach: f64) -> Option<Touch> {
        let rho2 = x.x * x.x + x.y * x.y;
        let inner = self.radius - self.height - reach;
        if inner > 0.0 && rho2 < inner * inner {
            return None;
        }
        let (k, _, w, dz, du, d2) = self.nearest([x.x, x.y, x.z]);
        let half = 0.5 * self.thickness;
        let reach_c = reach + half;
        if !(d2 > 0.0 && d2 < reach_c * reach_c) {
            return None;
        }
        let s = 1.0 - half / d2.sqrt();
        let (c, sn) = self.dirs[k];
        let (ru, rw, rz) = (du * s, w * s, dz * s);
        let r = V3::new(ru * c - rw * sn, ru * sn + rw * c, rz);
        Some(Touch { r, at: x - r })
    }

    /// Whether `x` is within `reach` of a lifter at any angle (in the annulus they sweep).
    pub fn near(&self, x: [f64; 3], reach: f64) -> bool {
        let inner = self.radius - self.height - reach;
        let in_span = match self.span {
            Some([lo, hi]) => {
                x[2] > lo - reach - self.thickness && x[2] < hi + reach + self.thickness
            }
            None => true,
        };
        in_span && (inner <= 0.0 || x[0] * x[0] + x[1] * x[1] > inner * inner)
    }

    /// Whether a sphere of radius `margin` at `x` is clear of every lifter.
    pub fn clear(&self, x: [f64; 3], margin: f64) -> bool {
        let d = 0.5 * self.thickness + margin;
        self.nearest(x).5 >= d * d
    }

    /// Area of one lifter's cross-section ([`Self::section`]): the rectangle and the half
    /// disc of its rounded tip.
    pub fn section_area(&self) -> f64 {
        let t = self.thickness;
        (self.radius - self.tip) * t + PI * t * t / 8.0
    }

    /// Axial length of the lifters: the span's, or `length` (the drum's) along the whole drum.
    pub fn length_in(&self, length: f64) -> f64 {
        self.span.map_or(length, |[lo, hi]| hi - lo)
    }

    /// Volume of the lifters (their rounded cross-section times their length; the rounded
    /// axial ends of a span are not counted).
    pub fn volume_in(&self, length: f64) -> f64 {
        self.count as f64 * self.section_area() * self.length_in(length)
    }

    /// The cross-section of lifter `k` at the present angle, in the `(x, y)` plane: the
    /// rectangle `tip <= u <= R`, `|w| <= thickness/2` (its corners, counter-clockwise) and
    /// the half disc of radius `thickness/2` about the tip's mid-line on the side `u <= tip`
    /// (its centre and the unit vector `e` along the lifter: the half disc is `p.e <= c.e`).
    /// The plate's corners at the root stick out of the curved wall by at most
    /// `thickness^2 / 8R`; they are counted (as in [`Self::volume_in`]).
    pub fn section(&self, k: usize) -> ([[f64; 2]; 4], [f64; 2], [f64; 2]) {
        let (c, s) = self.dirs[k];
        let hw = 0.5 * self.thickness;
        let at = |u: f64, w: f64| [u * c - w * s, u * s + w * c];
        (
            [
                at(self.tip, -hw),
                at(self.radius, -hw),
                at(self.radius, hw),
                at(self.tip, hw),
            ],
            at(self.tip, 0.0),
            [c, s],
        )
    }

    /// Area of the lifters' cross-sections ([`Self::section`]) below the height `y = h`, at
    /// the present angle: in closed form, each rectangle clipped by the line (a polygon) and
    /// each half disc clipped by it (a disc within a polygon).
    pub fn area_below(&self, h: f64) -> f64 {
        let r = 0.5 * self.thickness;
        (0..self.count)
            .map(|k| {
                let (rect, centre, e) = self.section(k);
                let plate = polygon_area(&clip_below(&rect, h));
                // the half disc: a square about its centre cut at u = tip and below y = h,
                // within the disc (coordinates from the centre)
                let b = 2.0 * r;
                let square = [[-b, -b], [b, -b], [b, b], [-b, b]];
                let half = clip(&square, |p| -(p[0] * e[0] + p[1] * e[1]));
                let below = clip(&half, |p| h - centre[1] - p[1]);
                plate + disc_in_polygon(r, &below)
            })
            .sum()
    }

    /// Each lifter as a box (`R - height <= u <= R`, `|w| <= thickness/2`, the span) at the
    /// present angle; `half` the drum's half length.
    pub fn mesh_in(&self, mesh: &mut DrumMesh, half: f64) {
        let [z0, z1] = self.span.unwrap_or([-half, half]);
        let (u0, u1, hw) = (self.radius - self.height, self.radius, 0.5 * self.thickness);
        // faces of the unit cube as corner indices (bit 0: u, bit 1: w, bit 2: z), outward
        const FACES: [[usize; 4]; 6] = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        for &(c, s) in &self.dirs {
            let o = mesh.points.len();
            for corner in 0..8 {
                let u = if corner & 1 == 0 { u0 } else { u1 };
                let w = if corner & 2 == 0 { -hw } else { hw };
                let z = if corner & 4 == 0 { z0 } else { z1 };
                mesh.points.push([u * c - w * s, u * s + w * c, z]);
            }
            for f in FACES {
                mesh.triangles.push([o + f[0], o + f[1], o + f[2]]);
                mesh.triangles.push([o + f[0], o + f[2], o + f[3]]);
            }
        }
    }
}

/// Refusals of the lifters' keys (`reach`: the wall reach of the largest particle).
pub(super) fn check(drum: &Drum, l: &DrumLifters, reach: f64, out: &mut Vec<(String, String)>) {
    let mut bad = |key: &str, why: String| out.push((format!("drum.lifters.{key}"), why));
    if drum.shape != Shape::Cylinder {
        bad(
            "count",
            "lifters are fixed to a cylinder's curved wall; a sphere or a cone has none here"
                .into(),
        );
        return;
    }
    if drum.rough_wall.is_some() {
        bad(
            "count",
            "lifters and a rough wall cannot be combined (the wall particles would sit inside \
             the lifters)"
                .into(),
        );
    }
    let r = 0.5 * drum.diameter;
    if l.count == 0 || l.count > 360 {
        bad("count", format!("must be 1 to 360, got {}", l.count));
    }
    if !(l.height > 0.0 && l.height < r) {
        bad(
            "height",
            format!(
                "must be positive and below the drum's radius {r} (a lifter reaches in from the \
                 wall), got {}",
                l.height
            ),
        );
    }
    if !(l.thickness > 0.0 && l.thickness <= l.height) {
        bad(
            "thickness",
            format!(
                "must be positive and at most the height {} (its tip is rounded with half the \
                 thickness), got {}",
                l.height, l.thickness
            ),
        );
    }
    if let Some([lo, hi]) = l.span {
        let half = 0.5 * drum.length.unwrap_or(0.0);
        if !(lo < hi && lo >= -half && hi <= half) {
            bad(
                "span",
                format!("must be [low, high] with -L/2 <= low < high <= L/2 (L/2 = {half}), got [{lo}, {hi}]"),
            );
        }
        if drum.periodic() {
            bad(
                "span",
                "a span would end the lifters inside a periodic drum, whose particles cross its \
                 ends: leave it out (lifters along the whole drum)"
                    .into(),
            );
        }
    }
    if !l.angle.is_finite() {
        bad("angle", format!("must be finite, got {}", l.angle));
    }
    // one history slot serves all lifters: no particle may touch two at once
    if l.count >= 2 && l.height < r && l.thickness <= l.height {
        let tip = r - l.height + 0.5 * l.thickness;
        let gap = 2.0 * tip * (PI / l.count as f64).sin() - l.thickness;
        if gap.is_nan() || gap <= 2.0 * reach {
            bad(
                "count",
                format!(
                    "{} lifters leave {gap:.4e} between neighbouring tips, less than twice the \
                     wall reach of the largest particle ({:.4e}): a particle could touch two \
                     lifters at once, and they share one contact history; use fewer or shorter \
                     lifters",
                    l.count,
                    2.0 * reach
                ),
            );
        }
    }
}

/// The part of a convex polygon (counter-clockwise) where `inside(p) >= 0`, for an affine
/// `inside` (Sutherland-Hodgman against one half-plane).
fn clip(poly: &[[f64; 2]], inside: impl Fn([f64; 2]) -> f64) -> Vec<[f64; 2]> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for (i, &a) in poly.iter().enumerate() {
        let b = poly[(i + 1) % poly.len()];
        let (fa, fb) = (inside(a), inside(b));
        if fa >= 0.0 {
            out.push(a);
        }
        if (fa >= 0.0) != (fb >= 0.0) {
            let t = fa / (fa - fb);
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    out
}

/// The part of a convex polygon below the height `y = h`.
fn clip_below(poly: &[[f64; 2]], h: f64) -> Vec<[f64; 2]> {
    clip(poly, |p| h - p[1])
}

/// Area of a polygon (counter-clockwise; 0 for fewer than three points).
fn polygon_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
}

/// Area of the disc of radius `r` about the origin within a polygon (counter-clockwise):
/// the sum over its edges `ab` of the signed area of the disc within the triangle `0ab`,
/// each edge cut where it crosses the circle into pieces inside (a triangle) or outside
/// (a circular sector).
fn disc_in_polygon(r: f64, poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    let r2 = r * r;
    let mut area = 0.0;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let d = [b[0] - a[0], b[1] - a[1]];
        // |a + t d|^2 = r^2
        let (qa, qb, qc) = (
            d[0] * d[0] + d[1] * d[1],
            a[0] * d[0] + a[1] * d[1],
            a[0] * a[0] + a[1] * a[1] - r2,
        );
        let mut ts = vec![0.0];
        let disc = qb * qb - qa * qc;
        if qa > 0.0 && disc > 0.0 {
            let root = disc.sqrt();
            for t in [(-qb - root) / qa, (-qb + root) / qa] {
                if t > 0.0 && t < 1.0 {
                    ts.push(t);
                }
            }
        }
        ts.push(1.0);
        let at = |t: f64| [a[0] + t * d[0], a[1] + t * d[1]];
        for w in ts.windows(2) {
            let (p, q) = (at(w[0]), at(w[1]));
            let cross = p[0] * q[1] - p[1] * q[0];
            let m = at(0.5 * (w[0] + w[1]));
            if m[0] * m[0] + m[1] * m[1] <= r2 {
                area += 0.5 * cross;
            } else {
                let dot = p[0] * q[0] + p[1] * q[1];
                area += 0.5 * r2 * cross.atan2(dot);
            }
        }
    }
    area
}
