//! The wall contact law on batches of wall contacts, lane by lane, as [`super::batch`] does
//! for the pairs.
//!
//! The walls' pass (`engine/wall_pass.rs`) finds each near-wall particle's wall points and
//! hands the contacts to [`BatchLaw::eval_walls`](super::batch::BatchLaw::eval_walls) [`LANES`] at a time, in struct-of-arrays
//! form ([`WallBatch`]). Each lane performs the IEEE operations of the scalar wall law
//! ([`ContactLaw::wall`](super::ContactLaw::wall)) in the same order, with the normal,
//! tangential, rolling and cohesion slots' lane functions that the pairs use: a wall is a
//! body of infinite mass and radius, so the effective mass is the particle's, the contact
//! diameter `d_iw` is also the effective radius, and the sliding velocity's lever is
//! `(d_iw) w x n` (Rapaport: `w x r'_iw`, as printed). The same bits as the scalar law on
//! every instruction set (`tests/contact_batch.rs`).

use super::batch::{cross, dot, scale, Coefficients, Col, Composed, LANES};
use super::cohesion::CohesionPart;
use super::contact::HISTORY_MAX;
use super::normal::NormalPart;
use super::rolling::{inv_inertia_at_surface, RollingPart};
use super::tangential::TangentialPart;

/// A batch of wall contacts, struct of arrays: what the law reads, the history it updates
/// and the force and torques it returns. Lanes past the contacts loaded hold the default
/// (a unit sphere at rest half overlapping a wall) or the previous batch's, finite either
/// way, and their results are ignored.
#[derive(Debug, Clone)]
pub struct WallBatch {
    /// From the wall point to the centre (its length is the distance).
    pub r: [Col; 3],
    /// The particle's velocity less the wall's at the wall point.
    pub v: [Col; 3],
    /// The particle's angular velocity.
    pub w: [Col; 3],
    /// The particle's diameter.
    pub d: Col,
    /// Its contact diameter with the wall (`NormalLaw::wall_contact`), also its effective
    /// radius.
    pub d_iw: Col,
    /// Its `1/m`.
    pub im: Col,
    /// The coefficients of the particle's material against the wall.
    pub coef: Coefficients,
    /// The drum's angular velocity about `+z` (the wall's spin, for rolling resistance).
    pub omega: f64,
    /// History words (the first [`BatchLaw::WORDS`](super::batch::BatchLaw::WORDS) read and
    /// written).
    pub hist: [Col; HISTORY_MAX],
    /// Force on the particle.
    pub force: [Col; 3],
    /// `(d/2) n x f_s`, subtracted from the particle's torque.
    pub torque: [Col; 3],
    /// The rolling torque, added to the particle's torque after `torque` is subtracted.
    pub roll: [Col; 3],
}

impl Default for WallBatch {
    fn default() -> Self {
        let z = [0.0; LANES];
        let one = [1.0; LANES];
        WallBatch {
            r: [[0.5; LANES], z, z],
            v: [z; 3],
            w: [z; 3],
            d: one,
            d_iw: [0.5; LANES],
            im: one,
            coef: Coefficients::default(),
            omega: 0.0,
            hist: [z; HISTORY_MAX],
            force: [z; 3],
            torque: [z; 3],
            roll: [z; 3],
        }
    }
}

/// Evaluate every lane of `b` with the composed law `law`:
/// [`BatchLaw::eval_walls`](super::batch::BatchLaw::eval_walls).
#[inline(always)]
pub(super) fn eval<N: NormalPart, T: TangentialPart, R: RollingPart, C: CohesionPart>(
    law: &Composed<N, T, R, C>,
    b: &mut WallBatch,
) {
    let col = |x: &[Col; 3], l: usize| [x[0][l], x[1][l], x[2][l]];
    for l in 0..LANES {
        let (r, v, w) = (col(&b.r, l), col(&b.v, l), col(&b.w, l));
        let (d, d_iw, im) = (b.d[l], b.d_iw[l], b.im[l]);
        let rr = dot(r, r).sqrt();
        let n = if N::DIVIDES {
            [r[0] / rr, r[1] / rr, r[2] / rr]
        } else {
            scale(r, 1.0 / rr)
        };
        let m_eff = 1.0 / im;
        let vn = dot(n, v);
        let (f_n, k_n, dash) = law.normal.lane(
            rr,
            d_iw,
            vn,
            m_eff,
            d_iw,
            b.coef.normal_k[l],
            b.coef.normal_c[l],
        );
        // the particle's surface point at the contact moves with v - (d/2) w x n
        let lever = if N::DIVIDES {
            cross(w, r)
        } else {
            scale(cross(w, n), d_iw)
        };
        let v_s = [
            v[0] - n[0] * vn - lever[0],
            v[1] - n[1] * vn - lever[1],
            v[2] - n[2] * vn - lever[2],
        ];
        let mut h = [b.hist[0][l], b.hist[1][l], b.hist[2][l]];
        let f_s = law.tangential.lane(
            n,
            v_s,
            f_n,
            k_n,
            dash,
            b.coef.gamma_s[l],
            b.coef.mu[l],
            &mut h,
        );
        if T::WORDS > 0 {
            for (k, hk) in h.iter().enumerate() {
                b.hist[k][l] = *hk;
            }
        }
        if R::ACTIVE {
            let o = T::WORDS;
            let mut h = [b.hist[o][l], b.hist[o + 1][l], b.hist[o + 2][l]];
            let w_rel = [w[0] - 0.0, w[1] - 0.0, w[2] - b.omega];
            let inv_ir = inv_inertia_at_surface(im, d);
            let t = law
                .rolling
                .lane(n, w_rel, f_n, k_n, d_iw, inv_ir, b.coef.mu_roll[l], &mut h);
            if R::WORDS > 0 {
                for (k, hk) in h.iter().enumerate() {
                    b.hist[o + k][l] = *hk;
                }
            }
            for (k, t) in t.iter().enumerate() {
                b.roll[k][l] = *t;
            }
        }
        let f_tot = if C::ACTIVE {
            f_n - law.cohesion.wall_lane(b.coef.cohesion[l], d_iw, rr)
        } else {
            f_n
        };
        let torque = scale(cross(n, f_s), 0.5 * d);
        for k in 0..3 {
            b.force[k][l] = n[k] * f_tot + f_s[k];
            b.torque[k][l] = torque[k];
        }
    }
}
