//! The force pass's second half, the pair contacts in canonical list order (the first, the
//! walls and gravity, is `wall_pass.rs`), and the instruction sets and law types both
//! halves are compiled for. The walls need no ghost, so the step computes them while the
//! ghosts' messages travel; every particle still sums its forces in the same order on any
//! number of ranks.

use super::neighbor::NeighborList;
use crate::particles::Particles;
use crate::physics::batch::{Batch, BatchLaw, Composed, LANES};
use crate::physics::cohesion::{CohesionPart, WithCohesion};
use crate::physics::contact::HISTORY_MAX;
use crate::physics::integrate::min_image;
use crate::physics::normal::{NormalPart, WithNormal};
use crate::physics::rolling::{RollingPart, WithRolling};
use crate::physics::tangential::{TangentialPart, WithTangential};
use crate::physics::{Body, ContactLaw, Materials, V3};

/// Particle `i` as the scalar laws see it, its diameter times `scale`.
#[inline]
pub(super) fn body(p: &Particles, i: usize, scale: f64) -> Body {
    Body {
        v: V3::from(p.v[i]),
        w: V3::from(p.w[i]),
        d: p.diameter[i] * scale,
        inv_mass: p.inv_mass[i],
    }
}

/// Add the pair contacts to the forces and torques of all local particles (after
/// [`wall_and_body_forces`](super::wall_pass::wall_and_body_forces)); `scale` multiplies every diameter (1 except while a pour
/// fill grows its particles).
///
/// The touching pairs are picked out of the list first, without a branch; their forces
/// are then computed [`LANES`] at a time by the run's law as a [`BatchLaw`] (vectorised,
/// with the widest instruction set this CPU has, see [`Isa`]) and added in list order.
/// The result is the same bits as [`pair_forces_reference`].
pub fn pair_forces(
    p: &mut Particles,
    nl: &mut NeighborList,
    law: &ContactLaw,
    mat: &Materials,
    period: Option<f64>,
    scale: f64,
) {
    pair_forces_with(Isa::detect(), p, nl, law, mat, period, scale)
}

/// [`pair_forces`] with a chosen instruction set (`Isa::Reference` is
/// [`pair_forces_reference`]); an instruction set this CPU lacks falls back to the best
/// it has.
pub fn pair_forces_with(
    isa: Isa,
    p: &mut Particles,
    nl: &mut NeighborList,
    law: &ContactLaw,
    mat: &Materials,
    period: Option<f64>,
    scale: f64,
) {
    if isa == Isa::Reference {
        return pair_forces_reference(p, nl, law, mat, period, scale);
    }
    let pass = Pass {
        mat,
        period,
        scale,
        law,
    };
    with_law(isa, law, PairPass { pass, p, nl })
}

/// The instruction sets the pair pass is compiled for, in increasing width. One binary
/// runs on any x86-64 and picks the widest its CPU has ([`Isa::detect`]); every choice gives
/// the same bits. `TUMBLER_ISA=reference|base|avx2|avx512` in the environment caps the choice
/// (for benchmarks and tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Isa {
    /// The per-pair scalar laws ([`pair_forces_reference`]).
    Reference,
    /// Batches with the target's baseline vectors (SSE2 on x86-64, NEON on aarch64).
    Base,
    /// Batches compiled for AVX2 (x86-64).
    Avx2,
    /// Batches compiled for AVX-512F (x86-64).
    Avx512,
}

impl Isa {
    /// The widest instruction set of this CPU, capped by `TUMBLER_ISA` if set.
    pub fn detect() -> Isa {
        static CHOSEN: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *CHOSEN.get_or_init(|| {
            let cpu = Isa::of_cpu();
            match std::env::var("TUMBLER_ISA").ok().as_deref() {
                Some("reference") => Isa::Reference,
                Some("base") => Isa::Base,
                Some("avx2") => cpu.min(Isa::Avx2),
                Some("avx512") => cpu.min(Isa::Avx512),
                _ => cpu,
            }
        })
    }

    /// The widest instruction set of this CPU.
    pub fn of_cpu() -> Isa {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return Isa::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Isa::Avx2;
            }
        }
        Isa::Base
    }

    /// Its name, as `TUMBLER_ISA` spells it.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Reference => "reference",
            Isa::Base => "base",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }
}

/// What a pair pass needs besides the particles and the list.
#[derive(Clone, Copy)]
struct Pass<'a> {
    mat: &'a Materials,
    period: Option<f64>,
    scale: f64,
    /// The run's law, for its cutoff while particles are scaled.
    law: &'a ContactLaw,
}

impl Pass<'_> {
    /// The pass itself, inlined into each instruction set's copy.
    #[inline(always)]
    fn run<L: BatchLaw>(self, law: &L, p: &mut Particles, nl: &mut NeighborList) {
        let m = self.touching(p, nl);
        if L::WORDS > 0 {
            Self::clear_parted(nl, m);
        }
        let touch = std::mem::take(&mut nl.touch);
        let mut b = Batch::default();
        for chunk in touch[..m].chunks(LANES) {
            self.gather::<L>(&mut b, chunk, p, nl);
            law.eval(&mut b);
            Self::scatter::<L>(&b, chunk, p, nl);
        }
        if L::WORDS > 0 {
            // this pass's touching pairs become the next pass's `touched_before`
            let mut before = std::mem::take(&mut nl.touched_spare);
            before.clear();
            before.extend_from_slice(&touch[..m]);
            nl.forget_touching();
            nl.touched_before = Some(before);
        }
        nl.touch = touch;
    }

    /// Put the list indices of the pairs that touch in `nl.touch`, in list order, and return
    /// how many. One pass over the list without a branch: the distance test only.
    #[inline(always)]
    fn touching(self, p: &Particles, nl: &mut NeighborList) -> usize {
        let n = nl.pairs.len();
        let touch = &mut nl.touch;
        if touch.len() < n + 1 {
            touch.resize(n + 1, 0);
        }
        let full_size = self.scale == 1.0;
        let mut m = 0;
        for (k, (&(a, b), &cut2)) in nl.pairs.iter().zip(&nl.cut2).enumerate() {
            let (a, b) = (a as usize, b as usize);
            let r = self.separation(p, a, b);
            let rc2 = if full_size {
                cut2
            } else {
                let rc = self
                    .law
                    .cutoff(p.diameter[a] * self.scale, p.diameter[b] * self.scale);
                rc * rc
            };
            let touches = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] < rc2;
            // written always, kept only when it touches: no branch to mispredict
            touch[m] = k as u32;
            m += touches as usize;
        }
        m
    }

    /// Clear the histories of the pairs that do not touch now (`nl.touch[..m]` are those
    /// that do). Only a pair that touched at the last pass can hold a history
    /// (`nl.touched_before`), so when that is known this is a merge of two short sorted
    /// lists; after a build it is a scan of the whole list. A history is written only when
    /// it is not zero already, as the scalar law's pass does (a `-0.0` stays as it is).
    fn clear_parted(nl: &mut NeighborList, m: usize) {
        let touch = &nl.touch[..m];
        let hist = &mut nl.hist;
        let mut clear = |k: usize| hist.clear_nonzero(k);
        let mut t = touch.iter().peekable();
        let mut not_touching = |k: u32| {
            while t.next_if(|&&x| x < k).is_some() {}
            t.peek() != Some(&&k)
        };
        match &nl.touched_before {
            Some(before) => {
                for &k in before {
                    if not_touching(k) {
                        clear(k as usize);
                    }
                }
            }
            None => {
                for k in 0..nl.pairs.len() as u32 {
                    if not_touching(k) {
                        clear(k as usize);
                    }
                }
            }
        }
    }

    /// `x_a - x_b`, the axial part the minimum image with periodic ends.
    #[inline(always)]
    fn separation(self, p: &Particles, a: usize, b: usize) -> [f64; 3] {
        let (xa, xb) = (p.x[a], p.x[b]);
        let mut dz = xa[2] - xb[2];
        if let Some(l) = self.period {
            dz = min_image(dz, l);
        }
        [xa[0] - xb[0], xa[1] - xb[1], dz]
    }

    /// Load a chunk of touching pairs into the batch's lanes.
    #[inline(always)]
    fn gather<L: BatchLaw>(self, b: &mut Batch, chunk: &[u32], p: &Particles, nl: &NeighborList) {
        for (l, &k) in chunk.iter().enumerate() {
            let (a, c) = nl.pairs[k as usize];
            let (a, c) = (a as usize, c as usize);
            let r = self.separation(p, a, c);
            let fr = self.mat.pair(p.species[a], p.species[c]);
            let (va, vc, wa, wc) = (p.v[a], p.v[c], p.w[a], p.w[c]);
            for q in 0..3 {
                b.r[q][l] = r[q];
                b.v[q][l] = va[q] - vc[q];
                b.wa[q][l] = wa[q];
                b.wb[q][l] = wc[q];
            }
            b.da[l] = p.diameter[a] * self.scale;
            b.db[l] = p.diameter[c] * self.scale;
            b.ima[l] = p.inv_mass[a];
            b.imb[l] = p.inv_mass[c];
            b.coef.load::<L>(l, &fr);
            match nl.hist.get(k as usize) {
                Some(h) => {
                    for (q, &h) in h.iter().enumerate() {
                        b.hist[q][l] = h;
                    }
                }
                None => {
                    for h in &mut b.hist[..L::WORDS] {
                        h[l] = 0.0;
                    }
                }
            }
        }
    }

    /// Add a batch's forces and torques in list order, and store its histories.
    #[inline(always)]
    fn scatter<L: BatchLaw>(b: &Batch, chunk: &[u32], p: &mut Particles, nl: &mut NeighborList) {
        for (l, &k) in chunk.iter().enumerate() {
            let (a, c) = nl.pairs[k as usize];
            let (a, c) = (a as usize, c as usize);
            for q in 0..3 {
                p.f[a][q] += b.force[q][l];
                p.f[c][q] -= b.force[q][l];
                p.t[a][q] -= b.torque_a[q][l];
                p.t[c][q] -= b.torque_b[q][l];
            }
            if L::WORDS > 0 {
                let mut h = [0.0; HISTORY_MAX];
                for (q, h) in h[..L::WORDS].iter_mut().enumerate() {
                    *h = b.hist[q][l];
                }
                nl.hist.set(k as usize, &h[..L::WORDS]);
            }
        }
    }
}

/// The pair pass with its particles and list, as a [`LawPass`].
struct PairPass<'a, 'b> {
    pass: Pass<'a>,
    p: &'b mut Particles,
    nl: &'b mut NeighborList,
}

impl LawPass for PairPass<'_, '_> {
    #[inline(always)]
    fn go<L: BatchLaw>(self, law: &L) {
        self.pass.run(law, self.p, self.nl)
    }
}

/// A pass over the particles that runs with the run's law made a type ([`with_law`]), so
/// that it is compiled once per composition of the law and per instruction set.
pub(super) trait LawPass {
    /// Run with `law`. Implementations are `#[inline(always)]`, so that each instruction
    /// set's copy ([`dispatch`]) compiles the whole pass with its instructions.
    fn go<L: BatchLaw>(self, law: &L);
}

/// Run `pass` with the law `model` made a type ([`Composed`]) and the instruction set
/// `isa` (at most what this CPU has).
pub(super) fn with_law<P: LawPass>(isa: Isa, model: &ContactLaw, pass: P) {
    let isa = isa.min(Isa::of_cpu());
    model.normal.visit(Compose {
        model,
        isa,
        law: (),
        pass,
    })
}

/// Run `pass` with `law`, compiled for `isa`.
fn dispatch<P: LawPass, L: BatchLaw>(isa: Isa, pass: P, law: &L) {
    match isa {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `isa` is at most what `Isa::of_cpu` found on this CPU (`with_law`).
        Isa::Avx512 => unsafe { go_avx512(pass, law) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        Isa::Avx2 => unsafe { go_avx2(pass, law) },
        _ => pass.go(law),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn go_avx512<P: LawPass, L: BatchLaw>(pass: P, law: &L) {
    pass.go(law)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn go_avx2<P: LawPass, L: BatchLaw>(pass: P, law: &L) {
    pass.go(law)
}

/// A law being made a type slot by slot: the normal, tangential, rolling and cohesion
/// models each turn themselves into a type ([`WithNormal`], [`WithTangential`],
/// [`WithRolling`], [`WithCohesion`]), so that the composition is one monomorphised pass.
struct Compose<'a, P, L> {
    model: &'a ContactLaw,
    isa: Isa,
    law: L,
    pass: P,
}

impl<P: LawPass> WithNormal for Compose<'_, P, ()> {
    type Out = ();
    fn with<N: NormalPart>(self, normal: N) {
        self.model.tangential.visit(Compose {
            model: self.model,
            isa: self.isa,
            law: normal,
            pass: self.pass,
        })
    }
}

impl<P: LawPass, N: NormalPart> WithTangential for Compose<'_, P, N> {
    type Out = ();
    fn with<T: TangentialPart>(self, tangential: T) {
        self.model.rolling.visit(Compose {
            model: self.model,
            isa: self.isa,
            law: Composed {
                normal: self.law,
                tangential,
                rolling: (),
                cohesion: (),
            },
            pass: self.pass,
        })
    }
}

impl<P: LawPass, N: NormalPart, T: TangentialPart> WithRolling
    for Compose<'_, P, Composed<N, T, (), ()>>
{
    type Out = ();
    fn with<R: RollingPart>(self, rolling: R) {
        let l = self.law;
        let law = Composed {
            normal: l.normal,
            tangential: l.tangential,
            rolling,
            cohesion: (),
        };
        self.model.cohesion.visit(Compose {
            model: self.model,
            isa: self.isa,
            law,
            pass: self.pass,
        })
    }
}

impl<P: LawPass, N: NormalPart, T: TangentialPart, R: RollingPart> WithCohesion
    for Compose<'_, P, Composed<N, T, R, ()>>
{
    type Out = ();
    fn with<C: CohesionPart>(self, cohesion: C) {
        let l = self.law;
        let law = Composed {
            normal: l.normal,
            tangential: l.tangential,
            rolling: l.rolling,
            cohesion,
        };
        dispatch(self.isa, self.pass, &law)
    }
}

/// The reference pair pass: each listed pair in turn through the scalar law
/// ([`ContactLaw::pair`]). [`pair_forces`] gives the same bits faster; this one is kept as
/// the reference that tests and benchmarks compare it with.
pub fn pair_forces_reference(
    p: &mut Particles,
    nl: &mut NeighborList,
    law: &ContactLaw,
    mat: &Materials,
    period: Option<f64>,
    scale: f64,
) {
    // the batched pass's record of touching pairs does not follow this pass
    nl.forget_touching();
    let full_size = scale == 1.0;
    let words = law.history_words();
    let rolling = law.has_rolling();
    for (k, (&(a, b), &cut2)) in nl.pairs.iter().zip(&nl.cut2).enumerate() {
        let mut hist = [0.0; HISTORY_MAX];
        if let Some(h) = nl.hist.get(k) {
            hist[..words].copy_from_slice(h);
        }
        let hist = &mut hist[..words];
        let (a, b) = (a as usize, b as usize);
        let xa = p.x[a];
        let xb = p.x[b];
        let mut dz = xa[2] - xb[2];
        if let Some(l) = period {
            dz = min_image(dz, l);
        }
        let r = V3::new(xa[0] - xb[0], xa[1] - xb[1], dz);
        // Most listed pairs are within the skin but not touching: reject them before
        // gathering their velocities (the law makes the same test, bit for bit).
        let rc2 = if full_size {
            cut2
        } else {
            let rc = law.cutoff(p.diameter[a] * scale, p.diameter[b] * scale);
            rc * rc
        };
        if r.norm_squared() >= rc2 {
            nl.hist.clear_nonzero(k);
            continue;
        }
        let (ba, bb) = (body(p, a, scale), body(p, b, scale));
        let c = law.pair(r, &ba, &bb, mat.pair(p.species[a], p.species[b]), hist);
        nl.hist.set(k, hist);
        let Some(c) = c else {
            continue;
        };
        let mut ta = c.n_cross_fs * (0.5 * ba.d);
        let mut tb = c.n_cross_fs * (0.5 * bb.d);
        if rolling {
            ta -= c.torque_roll;
            tb += c.torque_roll;
        }
        for k in 0..3 {
            p.f[a][k] += c.force[k];
            p.f[b][k] -= c.force[k];
            p.t[a][k] -= ta[k];
            p.t[b][k] -= tb[k];
        }
    }
}
