//! The pair contact laws evaluated on batches of touching pairs, lane by lane.
//!
//! The pair pass (`engine/forces.rs`) first picks out the listed pairs that touch, then hands
//! them to these kernels [`LANES`] at a time in struct-of-arrays form ([`Batch`]). Each lane
//! performs exactly the IEEE operations, in the same order, of the scalar laws of
//! [`super::ContactLaw`] (which stays the reference): their branches become selects whose
//! other side is computed and discarded, so the
//! loops over the lanes have no branch and the compiler vectorises them. Rust never
//! contracts `a * b + c` into a fused multiply-add nor uses approximate reciprocals, and
//! IEEE division and square root are correctly rounded in every width, so a lane gives the
//! same bits whatever the vector width: the SSE2, AVX2 and AVX-512 builds of
//! `engine::forces` and the scalar reference agree bit for bit (`tests/contact_batch.rs`).
//!
//! A law is a type implementing [`BatchLaw`], chosen once per force pass from the run's
//! [`ContactLaw`](super::ContactLaw), so the inner loop is monomorphised: no dispatch per
//! contact. The same law evaluates batches of wall contacts ([`BatchLaw::eval_walls`],
//! `wall_batch.rs`). A law is composed ([`Composed`]) of a normal part ([`NormalPart`]), a
//! tangential part ([`TangentialPart`]), rolling resistance and cohesion, each a small
//! type with one inlined lane function; Rapaport's law is one such composition.

use super::cohesion::{CohesionPart, NoCohesion};
use super::contact::HISTORY_MAX;
use super::normal::NormalPart;
use super::rapaport::Friction;
use super::rolling::{inv_inertia_at_surface, NoRolling, RollingPart};
use super::tangential::TangentialPart;
use super::wall_batch::WallBatch;

/// Pairs per batch: one AVX-512 register of `f64`, two of AVX2, four of SSE2.
pub const LANES: usize = 8;

/// One lane-wide column of `f64`.
pub type Col = [f64; LANES];

/// A batch of touching pairs, struct of arrays: the inputs a law reads, the history it
/// updates and the force and torques it returns. A law evaluates every lane; lanes past
/// the pairs loaded hold the default (a unit separation of unit spheres at rest) or the
/// previous batch's contacts, finite either way, and their results are ignored.
#[derive(Debug, Clone)]
pub struct Batch {
    /// `r = x_a - x_b` (minimum image).
    pub r: [Col; 3],
    /// `v_a - v_b`.
    pub v: [Col; 3],
    /// Angular velocity of `a`.
    pub wa: [Col; 3],
    /// Angular velocity of `b`.
    pub wb: [Col; 3],
    /// Diameter of `a`.
    pub da: Col,
    /// Diameter of `b`.
    pub db: Col,
    /// `1/m` of `a`.
    pub ima: Col,
    /// `1/m` of `b` (0 for a particle of a rough wall).
    pub imb: Col,
    /// The coefficients of the pair's materials.
    pub coef: Coefficients,
    /// History words (the first [`BatchLaw::WORDS`] read and written).
    pub hist: [Col; HISTORY_MAX],
    /// Force on `a` (`b` receives its negative).
    pub force: [Col; 3],
    /// `(d_a/2) n x f_s` less the rolling torque, subtracted from the torque of `a`.
    pub torque_a: [Col; 3],
    /// `(d_b/2) n x f_s` plus the rolling torque, subtracted from the torque of `b`.
    pub torque_b: [Col; 3],
}

impl Default for Batch {
    fn default() -> Self {
        let z = [0.0; LANES];
        let one = [1.0; LANES];
        Batch {
            r: [one, z, z],
            v: [z; 3],
            wa: [z; 3],
            wb: [z; 3],
            da: one,
            db: one,
            ima: one,
            imb: one,
            coef: Coefficients::default(),
            hist: [z; HISTORY_MAX],
            force: [z; 3],
            torque_a: [z; 3],
            torque_b: [z; 3],
        }
    }
}

/// The contact coefficients of a batch's lanes (a pair's or a wall contact's
/// [`Friction`]), one column each.
#[derive(Debug, Clone)]
pub struct Coefficients {
    /// Sliding friction coefficient `gamma_s`.
    pub gamma_s: Col,
    /// Static friction coefficient `mu`.
    pub mu: Col,
    /// Rolling friction coefficient `mu_r`.
    pub mu_roll: Col,
    /// Cohesion energy density `k_c`.
    pub cohesion: Col,
    /// Normal stiffness coefficient (`Friction::normal_k`; loaded only for a law of
    /// per-pair normal coefficients, [`BatchLaw::PAIR_NORMAL`]).
    pub normal_k: Col,
    /// Normal damping coefficient (`Friction::normal_c`; likewise).
    pub normal_c: Col,
}

impl Default for Coefficients {
    fn default() -> Self {
        let z = [0.0; LANES];
        Coefficients {
            gamma_s: z,
            mu: z,
            mu_roll: z,
            cohesion: z,
            normal_k: [1.0; LANES],
            normal_c: z,
        }
    }
}

impl Coefficients {
    /// Lane `l`'s coefficients from `fr`, the normal ones only for a law `L` of per-pair
    /// normal coefficients.
    #[inline(always)]
    pub fn load<L: BatchLaw>(&mut self, l: usize, fr: &Friction) {
        self.gamma_s[l] = fr.gamma_s;
        self.mu[l] = fr.mu;
        self.mu_roll[l] = fr.mu_roll;
        self.cohesion[l] = fr.cohesion;
        if L::PAIR_NORMAL {
            self.normal_k[l] = fr.normal_k;
            self.normal_c[l] = fr.normal_c;
        }
    }
}

/// A pair contact law on a batch.
pub trait BatchLaw: Copy {
    /// History words per contact (the first `WORDS` of `Batch::hist` read and written).
    const WORDS: usize;
    /// Whether it reads each pair's normal coefficients (`Batch::normal_k`, `normal_c`).
    const PAIR_NORMAL: bool = false;
    /// Evaluate every lane of `b`: `b.force`, `b.torque_a`, `b.torque_b` and, with a
    /// history, `b.hist`.
    fn eval(&self, b: &mut Batch);
    /// Evaluate every lane of the wall contacts `b`: `b.force`, `b.torque`, `b.roll` (with
    /// rolling resistance) and, with a history, `b.hist`.
    fn eval_walls(&self, b: &mut WallBatch);
}

/// The inputs of one lane, as the scalar laws see them.
#[derive(Debug, Clone, Copy)]
struct Lane {
    r: [f64; 3],
    v: [f64; 3],
    wa: [f64; 3],
    wb: [f64; 3],
    da: f64,
    db: f64,
    ima: f64,
    imb: f64,
    gamma_s: f64,
    mu: f64,
    mu_roll: f64,
    cohesion: f64,
    normal_k: f64,
    normal_c: f64,
}

impl Batch {
    #[inline(always)]
    fn lane(&self, l: usize) -> Lane {
        let c = |x: &[Col; 3]| [x[0][l], x[1][l], x[2][l]];
        Lane {
            r: c(&self.r),
            v: c(&self.v),
            wa: c(&self.wa),
            wb: c(&self.wb),
            da: self.da[l],
            db: self.db[l],
            ima: self.ima[l],
            imb: self.imb[l],
            gamma_s: self.coef.gamma_s[l],
            mu: self.coef.mu[l],
            mu_roll: self.coef.mu_roll[l],
            cohesion: self.coef.cohesion[l],
            normal_k: self.coef.normal_k[l],
            normal_c: self.coef.normal_c[l],
        }
    }

    #[inline(always)]
    fn put(&mut self, l: usize, force: [f64; 3], n_cross_fs: [f64; 3], da: f64, db: f64) {
        let (ha, hb) = (0.5 * da, 0.5 * db);
        for k in 0..3 {
            self.force[k][l] = force[k];
            self.torque_a[k][l] = n_cross_fs[k] * ha;
            self.torque_b[k][l] = n_cross_fs[k] * hb;
        }
    }
}

// Vector helpers with nalgebra's operation order (`dot` = `x + y + z` of the products,
// `cross` as `Vector3::cross`), so that a lane repeats the scalar laws' arithmetic.
#[inline(always)]
pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
pub(super) fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[inline(always)]
pub(super) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[inline(always)]
pub(super) fn select3(c: bool, a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        if c { a[0] } else { b[0] },
        if c { a[1] } else { b[1] },
        if c { a[2] } else { b[2] },
    ]
}

/// A composed law on a batch: normal part `N`, tangential part `T`, rolling `R` and
/// cohesion `C`. Each is a type, so a run's composition is one monomorphised loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Composed<N, T, R = NoRolling, C = NoCohesion> {
    /// Normal part.
    pub normal: N,
    /// Tangential part.
    pub tangential: T,
    /// Rolling resistance.
    pub rolling: R,
    /// Cohesion.
    pub cohesion: C,
}

impl<N: NormalPart, T: TangentialPart, R: RollingPart, C: CohesionPart> BatchLaw
    for Composed<N, T, R, C>
{
    const WORDS: usize = T::WORDS + R::WORDS;
    const PAIR_NORMAL: bool = N::PAIRS;

    #[inline(always)]
    fn eval(&self, b: &mut Batch) {
        for l in 0..LANES {
            let s = b.lane(l);
            let d_ab = 0.5 * (s.da + s.db);
            let rr = dot(s.r, s.r).sqrt();
            let n = if N::DIVIDES {
                [s.r[0] / rr, s.r[1] / rr, s.r[2] / rr]
            } else {
                scale(s.r, 1.0 / rr)
            };
            let m_eff = 1.0 / (s.ima + s.imb);
            let inv_d = 1.0 / (s.da + s.db);
            let vn = dot(n, s.v);
            let r_eff = 0.5 * s.da * s.db * inv_d;
            let (f_n, k_n, dash) = self
                .normal
                .lane(rr, d_ab, vn, m_eff, r_eff, s.normal_k, s.normal_c);
            // sliding velocity with both spins (thesis eq. 2.16, Rapaport eq. 3)
            let w_eff = if N::DIVIDES {
                let sum_d = s.da + s.db;
                [
                    (s.wa[0] * s.da + s.wb[0] * s.db) / sum_d,
                    (s.wa[1] * s.da + s.wb[1] * s.db) / sum_d,
                    (s.wa[2] * s.da + s.wb[2] * s.db) / sum_d,
                ]
            } else {
                [
                    (s.wa[0] * s.da + s.wb[0] * s.db) * inv_d,
                    (s.wa[1] * s.da + s.wb[1] * s.db) * inv_d,
                    (s.wa[2] * s.da + s.wb[2] * s.db) * inv_d,
                ]
            };
            let wxr = cross(w_eff, s.r);
            let v_s = [
                s.v[0] - n[0] * vn - wxr[0],
                s.v[1] - n[1] * vn - wxr[1],
                s.v[2] - n[2] * vn - wxr[2],
            ];
            let mut h = [b.hist[0][l], b.hist[1][l], b.hist[2][l]];
            let f_s = self
                .tangential
                .lane(n, v_s, f_n, k_n, dash, s.gamma_s, s.mu, &mut h);
            if T::WORDS > 0 {
                for (k, hk) in h.iter().enumerate() {
                    b.hist[k][l] = *hk;
                }
            }
            let roll = if R::ACTIVE {
                // the rolling spring's words follow the tangential spring's
                let o = T::WORDS;
                let mut h = [b.hist[o][l], b.hist[o + 1][l], b.hist[o + 2][l]];
                let w_rel = [s.wa[0] - s.wb[0], s.wa[1] - s.wb[1], s.wa[2] - s.wb[2]];
                let inv_ir =
                    inv_inertia_at_surface(s.ima, s.da) + inv_inertia_at_surface(s.imb, s.db);
                let t = self
                    .rolling
                    .lane(n, w_rel, f_n, k_n, r_eff, inv_ir, s.mu_roll, &mut h);
                if R::WORDS > 0 {
                    for (k, hk) in h.iter().enumerate() {
                        b.hist[o + k][l] = *hk;
                    }
                }
                t
            } else {
                [0.0; 3]
            };
            let f_tot = if C::ACTIVE {
                f_n - self.cohesion.lane(s.cohesion, 0.5 * s.da, 0.5 * s.db, rr)
            } else {
                f_n
            };
            let force = [
                n[0] * f_tot + f_s[0],
                n[1] * f_tot + f_s[1],
                n[2] * f_tot + f_s[2],
            ];
            b.put(l, force, cross(n, f_s), s.da, s.db);
            if R::ACTIVE {
                for (k, r) in roll.iter().enumerate() {
                    b.torque_a[k][l] -= r;
                    b.torque_b[k][l] += r;
                }
            }
        }
    }

    #[inline(always)]
    fn eval_walls(&self, b: &mut WallBatch) {
        super::wall_batch::eval(self, b)
    }
}
