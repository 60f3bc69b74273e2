//! The simulation state of one rank and the step loop.

use super::balance;
use super::forces::pair_forces;
use super::halo::{self, Halo, UpdateBuffers};
use super::neighbor::{
    push_record, read_record, record_words, sort_saved, Grid, NeighborList, SavedContact,
    SavedHistory,
};
use super::order::KeyGrid;
use super::slabs::Slabs;
use super::timers::{Phase, Timers};
use super::wall_pass::{wall_and_body_forces, WallForces, WallScratch};
use crate::case::Case;
use crate::comm::Comm;
use crate::particles::{ParticleState, Particles, Records};
use crate::physics::integrate::{drift, half_kick, min_image};
use crate::physics::rough_wall::{is_fixed, RoughWall};
use crate::physics::{law, ContactLaw, DrumWalls, Materials};
use std::time::Instant;

/// Bins of the load-balance histogram per interaction range + skin: fine enough that a cut
/// on a bin edge leaves a slab within a few per cent of its share on a bed of a few hundred
/// particles per rank.
const BALANCE_BINS_PER_REACH: f64 = 32.0;

/// What a load-balance check found: the imbalance (max / mean work per rank) before and
/// after it, and the smallest any slabs as wide as the halo can reach.
#[derive(Debug, Clone, Copy)]
pub struct BalanceCheck {
    /// With the slabs as they were.
    pub before: f64,
    /// With the slabs after the check (`before` if they did not move).
    pub after: f64,
    /// The least any slabs longer than the halo width can reach ([`balance::imbalance_bound`]).
    pub bound: f64,
}

/// Why a decomposition cannot be used.
#[derive(Debug, Clone, PartialEq)]
pub struct DecompositionError(pub String);

/// The slabs a run starts with on `ranks` ranks (equal lengths), whose particles each rank
/// makes or reads for itself.
pub fn initial_slabs(case: &Case, ranks: usize) -> Slabs {
    Slabs::uniform(ranks, case.drum.axial_length(), case.drum.periodic())
}

/// Refuse cutting the drum of `case` into `ranks` equal slabs thinner than the interaction
/// range + skin (a ghost must come from a neighbouring slab), saying how many ranks fit.
pub fn slabs_fit(case: &Case, ranks: usize) -> Result<(), String> {
    let length = case.drum.axial_length();
    let width = initial_slabs(case, ranks).min_width();
    let reach = law::reach(case);
    if width < reach {
        return Err(format!(
            "{ranks} ranks cut the drum (length {length}) into slabs {width:.3} long, thinner \
             than the interaction range + skin {reach:.3}; use at most {} ranks",
            ((length / reach).floor() as usize).max(1)
        ));
    }
    Ok(())
}

impl std::fmt::Display for DecompositionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// One rank's share of a run: its slab, its particles and ghosts, and the machinery of a step.
pub struct Sim<'c> {
    comm: &'c dyn Comm,
    /// The case being run.
    pub case: Case,
    /// The contact law.
    pub law: ContactLaw,
    /// Friction tables and material constants.
    pub mat: Materials,
    /// The drum's walls.
    pub walls: DrumWalls,
    /// The rough wall's particles, if the curved wall has them.
    pub rough: Option<RoughWall>,
    /// The slab decomposition.
    pub slabs: Slabs,
    /// Owned particles, then ghosts.
    pub p: Particles,
    halo: Halo,
    ghost_bufs: UpdateBuffers,
    /// The walls' pass's lists, kept between steps.
    wall_scratch: WallScratch,
    nl: NeighborList,
    /// Steps taken since time zero.
    pub step: u64,
    /// Time step.
    pub dt: f64,
    /// Verlet skin.
    pub skin: f64,
    /// Gravitational acceleration along `-y` (the case's, except while a pour grows).
    pub gravity: f64,
    /// Factor on every diameter in the contacts (1, except while a pour grows).
    pub scale: f64,
    /// Interaction range of the largest pair plus the skin: the halo width and cell size.
    pub reach: f64,
    /// The grid of the particles' order keys.
    keys: KeyGrid,
    /// Steps between spatial sorts (0: never).
    sort_every: u64,
    /// Time per phase.
    pub timers: Timers,
    /// Neighbour-list rebuilds so far.
    pub rebuilds: u64,
    /// Particles this rank sent to neighbours by migration so far.
    pub migrated: u64,
    /// Contact histories this rank sent along with migrating particles so far.
    pub histories_migrated: u64,
    /// Rebuilds that needed the irregular exchange (particles to any rank) so far.
    pub irregular_migrations: u64,
    /// What went wrong in a step that cannot go on (a particle that moved past a whole slab
    /// between two list builds, a non-finite position): reported by [`Sim::health`].
    fault: Option<String>,
}

impl<'c> Sim<'c> {
    /// Set up a rank from its part of the initial state (it keeps the particles of
    /// `initial` in its own slab of [`initial_slabs`]), and compute the initial forces.
    pub fn new(
        case: &Case,
        comm: &'c dyn Comm,
        initial: &[ParticleState],
    ) -> Result<Self, DecompositionError> {
        let mut sim = Self::assemble(case, comm, initial)?;
        let order = if sim.sort_every > 0 {
            Reorder::Sort
        } else {
            Reorder::Keep
        };
        sim.rebuild_with(Vec::new(), true, order);
        sim.forces_advancing(true);
        Ok(sim)
    }

    /// Continue a run from a checkpoint's particles (with their last forces), contact
    /// histories and step, on this communicator's ranks; the next `step()` is the one the
    /// interrupted run would have taken.
    ///
    /// Each rank passes its own share of the checkpoint, as read: `particles` sorted by id,
    /// the ranks' shares in increasing order of id (rows `[r N/P, (r+1) N/P)`, say), and any
    /// share of the histories, each held by one rank. A history first goes to the ranks that
    /// hold its two particles, then particles go to the ranks that own their `z` with the
    /// histories they are part of, as after a rebalance (the irregular migration).
    pub fn resume(
        case: &Case,
        comm: &'c dyn Comm,
        particles: &Records,
        histories: SavedHistory,
        step: u64,
    ) -> Result<Self, DecompositionError> {
        let mut sim = Self::assemble(case, comm, &[])?;
        let saved = sim.route_to_holders(particles, histories);
        for s in particles.states() {
            sim.p.push_owned(&s, &sim.mat);
        }
        sim.step = step;
        sim.turn_drum(sim.walls.omega * step as f64 * sim.dt);
        sim.rough_wall_keys();
        sim.rebuild_with(saved, true, Reorder::KeysOfSaved);
        Ok(sim)
    }

    /// Give the rough wall's particles (which checkpoints do not hold: `assemble` makes them)
    /// the keys of the last sort, at or before this step: where the drum had carried them
    /// then (at the start of the run, or at the end of a pour, where the drum stood still:
    /// at angle 0).
    fn rough_wall_keys(&mut self) {
        let Some(rw) = self.rough.filter(|_| self.sort_every > 0) else {
            return;
        };
        let last = self.step / self.sort_every * self.sort_every;
        // the angle `step()` turns the drum to before that sort
        let angle = self.walls.omega * last as f64 * self.dt;
        for i in 0..self.p.n_owned {
            if is_fixed(self.p.species[i]) {
                let x = rw.place(self.p.id[i], angle, self.walls.omega).0;
                self.p.key[i] = self.keys.key(x);
            }
        }
    }

    /// Send each history of `histories` to the ranks that hold its particles: for a mobile
    /// particle, the rank whose share of `particles` (ranks in increasing order of id) has its
    /// id; for a rough wall's, the owner of its `z`, where `assemble` put it. Returns the
    /// histories this rank receives, sorted by ids (their keys are not known yet).
    fn route_to_holders(&self, particles: &Records, histories: SavedHistory) -> SavedHistory {
        let (me, size) = (self.comm.rank(), self.comm.size());
        let mut first = vec![0u64; 2 * size];
        if !particles.is_empty() {
            first[2 * me] = particles.id(0);
            first[2 * me + 1] = 1;
        }
        self.comm.sum_u64_all(&mut first);
        let starts: Vec<(u64, usize)> = (0..size)
            .filter(|&r| first[2 * r + 1] == 1)
            .map(|r| (first[2 * r], r))
            .collect();
        let omega = self.walls.omega;
        let holder = |id: u64| -> usize {
            if let Some(rw) = self
                .rough
                .filter(|_| id >= crate::physics::rough_wall::FIRST_ID)
            {
                return self.slabs.owner(rw.place(id, 0.0, omega).0[2]);
            }
            let k = starts.partition_point(|x| x.0 <= id);
            starts.get(k.saturating_sub(1)).map_or(0, |x| x.1)
        };
        let words = self.p.hist_words;
        let ranks_of = |rec: &SavedContact| {
            let (ra, rb) = (holder(rec.a), holder(rec.b));
            [Some(ra), (rb != ra).then_some(rb)].into_iter().flatten()
        };
        let mut counts = vec![0usize; size];
        for rec in &histories {
            for r in ranks_of(rec) {
                counts[r] += record_words(words);
            }
        }
        let mut to: Vec<Vec<f64>> = counts.iter().map(|&c| Vec::with_capacity(c)).collect();
        for rec in &histories {
            for r in ranks_of(rec) {
                push_record(&mut to[r], rec, words);
            }
        }
        drop(histories);
        let got = self.comm.all_to_all(to);
        let mut saved: SavedHistory = got
            .iter()
            .flat_map(|m| m.chunks_exact(record_words(words)))
            .map(|r| read_record(r, words))
            .collect();
        sort_saved(&mut saved);
        saved
    }

    /// The rank's particles and machinery, before any list or force.
    fn assemble(
        case: &Case,
        comm: &'c dyn Comm,
        initial: &[ParticleState],
    ) -> Result<Self, DecompositionError> {
        let mat = Materials::new(case);
        slabs_fit(case, comm.size()).map_err(DecompositionError)?;
        let reach = law::reach(case);
        let slabs = initial_slabs(case, comm.size());
        let walls = DrumWalls::of(&case.drum);
        let radius = walls.radius;
        let mut p = Particles::new(law::ContactLaw::new(case).history_words());
        let me = comm.rank();
        for s in initial.iter().filter(|s| slabs.owner(s.x[2]) == me) {
            p.push_owned(s, &mat);
        }
        let rough = RoughWall::of(case);
        if let Some(rw) = &rough {
            for s in rw
                .particles(case.drum.omega)
                .iter()
                .filter(|s| slabs.owner(s.x[2]) == me)
            {
                p.push_owned(s, &mat);
            }
        }
        let sim = Sim {
            comm,
            case: case.clone(),
            law: ContactLaw::new(case),
            mat,
            walls,
            rough,
            slabs,
            p,
            halo: Halo::default(),
            ghost_bufs: UpdateBuffers::default(),
            wall_scratch: WallScratch::default(),
            nl: NeighborList::default(),
            step: 0,
            dt: case.dt(),
            skin: case.skin(),
            gravity: case.model.gravity,
            scale: 1.0,
            reach,
            // cells of the interaction range: not of the reach, or the order (and so the last
            // bits of a run) would depend on the skin
            keys: KeyGrid::new(radius, case.drum.axial_length(), law::range(case)),
            sort_every: case.run.sort_every,
            timers: Timers::default(),
            rebuilds: 0,
            migrated: 0,
            histories_migrated: 0,
            irregular_migrations: 0,
            fault: None,
        };
        Ok(sim)
    }

    fn period(&self) -> Option<f64> {
        self.slabs.periodic.then_some(self.slabs.length)
    }

    /// Time since the drum started turning.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }

    /// Drum rotations completed so far.
    pub fn rotations(&self) -> f64 {
        self.time() * self.case.drum.omega.abs() / (2.0 * std::f64::consts::PI)
    }

    /// The communicator this rank uses.
    pub fn comm(&self) -> &'c dyn Comm {
        self.comm
    }

    /// Advance one time step (velocity Verlet): half kick, drift, halo (rebuilt, or refreshed
    /// while the wall forces are computed), forces, half kick.
    pub fn step(&mut self) {
        let dt = self.dt;
        let period = self.period();
        self.half_kick();
        let (n, p) = (self.p.n_owned, &mut self.p);
        self.timers
            .time(Phase::Integrate, || drift(n, dt, &mut p.x, &p.v, period));
        self.turn_drum(self.walls.omega * (self.step + 1) as f64 * dt);
        // The ranks agree on the largest displacement since the last list build while the
        // ghosts' refresh travels, so that one wait per step serves both; the wall forces are
        // computed then too, unless the displacement calls for a rebuild (which discards the
        // refreshed ghosts). A non-finite position anywhere is carried by the maximum (as
        // infinity) so that every rank stops together with the same message.
        let sort = self.sort_every > 0 && (self.step + 1).is_multiple_of(self.sort_every);
        let moved = self.update_ghosts_during_wall_forces(true, Some(sort));
        if moved.is_infinite() {
            // Stop at the next health check (every rank knows: the maximum is global); until
            // then nothing is rebuilt from the bad coordinates.
            if self.fault.is_none() {
                let here = (0..self.p.n_owned)
                    .find(|&i| self.p.x[i].iter().any(|c| !c.is_finite()))
                    .map(|i| {
                        format!(
                            " (particle {}, species {})",
                            self.p.id[i], self.p.species[i]
                        )
                    })
                    .unwrap_or_else(|| " (on another rank)".into());
                self.fault = Some(format!(
                    "run stopped: a particle position became infinite or NaN at step {}{here}; the \
                     time step is too large for the contact stiffness or damping (see `tumbler check`)",
                    self.step
                ));
            }
        } else if rebuild_due(moved, self.skin, sort) {
            self.rebuild(sort);
            self.wall_and_body_forces(true);
        }
        self.pair_forces(true);
        self.half_kick();
        self.step += 1;
    }

    /// `v += dt/2 F/m`, `w += dt/2 T/I` for the owned particles (whose number migration may
    /// have changed since the last kick).
    fn half_kick(&mut self) {
        let (n, h, p) = (self.p.n_owned, 0.5 * self.dt, &mut self.p);
        self.timers.time(Phase::Integrate, || {
            half_kick(
                n,
                h,
                &mut p.v,
                &mut p.w,
                &p.f,
                &p.t,
                &p.inv_mass,
                &p.inv_inertia,
            )
        });
    }

    /// Refresh the ghosts' positions, velocities and spins from their owners, computing the
    /// owned particles' wall forces and gravity (the first half of the force pass, which
    /// needs no ghost) while the messages travel.
    ///
    /// With `decide = Some(sort)`, the ranks also agree, while the messages travel, on the
    /// largest displacement of a particle since the last list build, which is returned
    /// (infinite if some position is not finite), and the wall forces are left out if it
    /// calls for a rebuild ([`rebuild_due`]); with `None`, 0 is returned.
    fn update_ghosts_during_wall_forces(&mut self, advance: bool, decide: Option<bool>) -> f64 {
        let law = self.law_advancing(advance);
        let start = Instant::now();
        let local = match decide {
            Some(_) => self.nl.max_displacement(&self.p, self.period()),
            None => 0.0,
        };
        let (p, halo, slabs, comm, bufs) = (
            &mut self.p,
            &self.halo,
            &self.slabs,
            self.comm,
            &mut self.ghost_bufs,
        );
        let env = WallForces {
            walls: &self.walls,
            law: &law,
            mat: &self.mat,
            gravity: self.gravity,
            scale: self.scale,
        };
        let (near, scratch) = (&self.nl.near_walls, &mut self.wall_scratch);
        let skin = self.skin;
        let mut moved = 0.0;
        let mut wall_secs = 0.0;
        halo::update_ghosts(p, halo, slabs, comm, bufs, &mut |p| {
            if let Some(sort) = decide {
                moved = comm.max_f64(if local.is_nan() { f64::INFINITY } else { local });
                if rebuild_due(moved, skin, sort) {
                    return;
                }
            }
            let t0 = Instant::now();
            wall_and_body_forces(p, near, scratch, &env);
            wall_secs += t0.elapsed().as_secs_f64();
        });
        let total = start.elapsed().as_secs_f64();
        self.timers.add(Phase::Walls, wall_secs);
        self.timers.add(Phase::Comm, total - wall_secs);
        moved
    }

    /// Turn the drum to the angle `angle`: its lifters, and the rough wall's particles
    /// placed where the drum has carried them.
    fn turn_drum(&mut self, angle: f64) {
        self.walls.turn_to(angle);
        let Some(rw) = self.rough else { return };
        let omega = self.walls.omega;
        for i in 0..self.p.n_owned {
            if is_fixed(self.p.species[i]) {
                let (x, v) = rw.place(self.p.id[i], angle, omega);
                self.p.x[i] = x;
                self.p.v[i] = v;
                self.p.w[i] = [0.0, 0.0, omega];
            }
        }
    }

    /// Migrate particles that left the slab, rebuild the halo and the pair list; with
    /// `sort`, give every particle the order key of where it is now.
    fn rebuild(&mut self, sort: bool) {
        let saved = self.saved_histories();
        let order = if sort { Reorder::Sort } else { Reorder::Keep };
        self.rebuild_with(saved, false, order);
    }

    fn saved_histories(&self) -> SavedHistory {
        if self.law.has_history() {
            self.nl.save_histories(&self.p)
        } else {
            Vec::new()
        }
    }

    /// Migrate, rebuild the halo and the pair list, giving the pairs the histories of
    /// `saved`. `bounds_moved`: the slab boundaries changed since the last build (or there was
    /// none), so particles may go to any rank; otherwise one that does has moved past a whole
    /// slab since the last build, and the run is stopped at the next health check.
    /// `order`: what the particles' order keys and `saved`'s need.
    fn rebuild_with(&mut self, mut saved: SavedHistory, bounds_moved: bool, order: Reorder) {
        let history = self.law.has_history();
        let (p, slabs, comm, mat, reach, keys) = (
            &mut self.p,
            &self.slabs,
            self.comm,
            &self.mat,
            self.reach,
            &self.keys,
        );
        let (moved, halo) = self.timers.time(Phase::Comm, || {
            p.clear_ghosts();
            let moved = halo::migrate(p, slabs, comm, mat, &mut saved);
            if order == Reorder::Sort {
                keys.set_keys(p);
            }
            if order != Reorder::Keep {
                p.sort_owned();
            }
            let halo = halo::borders(p, slabs, comm, mat, reach);
            p.trim();
            (moved, halo)
        });
        if order != Reorder::Keep && !saved.is_empty() {
            give_keys(&self.p, &mut saved);
        }
        self.migrated += moved.particles as u64;
        self.histories_migrated += moved.histories as u64;
        self.irregular_migrations += moved.irregular as u64;
        if let (Some((id, z, owner)), false, None) = (moved.far, bounds_moved, &self.fault) {
            self.fault = Some(format!(
                "run stopped at step {}: particle {id} moved past a whole slab between two \
                 neighbour-list builds (it is at z = {z:.6e}, in the slab of rank {owner}; slabs \
                 are at least {:.4e} long and lists are rebuilt before anything moves half the \
                 skin {:.4e}), so contacts were missed: the time step is probably too large for \
                 the contact stiffness or damping (see `tumbler check`), or the particles were \
                 started too fast",
                self.step,
                self.slabs.min_width(),
                self.skin
            ));
        }
        self.halo = halo;
        // the slab and its halo, inside the drum
        let (z_lo, z_hi) = self.slabs.range(self.comm.rank());
        let r = self.walls.radius + self.reach;
        let (box_lo, box_hi) = ([-r, -r, z_lo - self.reach], [r, r, z_hi + self.reach]);
        let (nl, p, skin, law, reach) =
            (&mut self.nl, &mut self.p, self.skin, &self.law, self.reach);
        let walls = &self.walls;
        self.timers.time(Phase::Neighbor, || {
            // cells over the particles' bounding box: they grow with the bed, not the drum
            let cell = reach / super::neighbor::SPAN as f64;
            nl.build(p, &Grid::around(p, cell, box_lo, box_hi), skin, law);
            nl.list_near_walls(p, walls, law, skin);
            if history {
                nl.attach_histories(p, &saved);
            }
        });
        self.rebuilds += 1;
    }

    /// The law of the force pass; `advance = false` recomputes the forces of the current
    /// instant without adding another step's sliding to the tangential histories.
    fn law_advancing(&self, advance: bool) -> ContactLaw {
        if advance {
            self.law
        } else {
            self.law.frozen()
        }
    }

    /// The first half of the force pass: forces zeroed, then the walls and gravity.
    fn wall_and_body_forces(&mut self, advance: bool) {
        let law = self.law_advancing(advance);
        let env = WallForces {
            walls: &self.walls,
            law: &law,
            mat: &self.mat,
            gravity: self.gravity,
            scale: self.scale,
        };
        let (p, near, scratch) = (&mut self.p, &self.nl.near_walls, &mut self.wall_scratch);
        self.timers.time(Phase::Walls, || {
            wall_and_body_forces(p, near, scratch, &env)
        });
    }

    /// The second half of the force pass: the pair contacts.
    fn pair_forces(&mut self, advance: bool) {
        let period = self.period();
        let law = self.law_advancing(advance);
        let (p, nl, mat, scale) = (&mut self.p, &mut self.nl, &self.mat, self.scale);
        self.timers.time(Phase::Pairs, || {
            pair_forces(p, nl, &law, mat, period, scale)
        });
    }

    /// The whole force pass.
    fn forces_advancing(&mut self, advance: bool) {
        self.wall_and_body_forces(advance);
        self.pair_forces(advance);
    }

    /// Remove the owned particles for which `cut` holds (all ranks call this together), and
    /// rebuild so that the halo and lists forget them.
    pub fn remove_where(&mut self, cut: impl Fn(&ParticleState) -> bool) {
        let saved = self.saved_histories();
        self.p.clear_ghosts();
        let leave: Vec<bool> = (0..self.p.n_owned)
            .map(|i| !is_fixed(self.p.species[i]) && cut(&self.p.state(i)))
            .collect();
        self.p.remove_owned(&leave);
        self.rebuild_with(saved, false, Reorder::Keep);
        self.forces_advancing(false);
    }

    /// Work per rank (particles plus listed pairs) with the current slabs, on every rank.
    pub fn work_per_rank(&self) -> Vec<u64> {
        let (hist, z0, length) = self.work_histogram();
        balance::work_per_slab(&hist, z0, length, &self.slabs.bounds)
    }

    /// The work histogram along the axis, summed over all ranks: each owned particle counts
    /// one plus the listed pairs it belongs to, in bins of 1/32 of the interaction range + skin.
    fn work_histogram(&self) -> (Vec<u64>, f64, f64) {
        let length = self.slabs.length;
        let z0 = -0.5 * length;
        let nb = ((BALANCE_BINS_PER_REACH * length / self.reach).ceil() as usize).clamp(1, 1 << 22);
        let mut per = vec![1u64; self.p.len()];
        for &(a, b) in &self.nl.pairs {
            per[a as usize] += 1;
            per[b as usize] += 1;
        }
        let mut hist = vec![0u64; nb];
        for i in 0..self.p.n_owned {
            let k = ((self.p.x[i][2] - z0) / length * nb as f64).floor();
            hist[(k.max(0.0) as usize).min(nb - 1)] += per[i];
        }
        self.comm.sum_u64_all(&mut hist);
        (hist, z0, length)
    }

    /// Move the slab boundaries so that every rank has the same work, if the imbalance
    /// (max / mean work per rank) exceeds `tolerance`; all ranks call this together. The
    /// particles move to their new owners at once (a rebuild).
    pub fn rebalance(&mut self, tolerance: f64) -> BalanceCheck {
        let (hist, z0, length) = self.work_histogram();
        let ranks = self.comm.size();
        let before = balance::imbalance(&balance::work_per_slab(
            &hist,
            z0,
            length,
            &self.slabs.bounds,
        ));
        let bound = balance::imbalance_bound(&hist, length, ranks, self.reach);
        let unmoved = BalanceCheck {
            before,
            after: before,
            bound,
        };
        if before <= tolerance || ranks == 1 {
            return unmoved;
        }
        let Some(bounds) = balance::balanced_bounds(&hist, z0, length, ranks, self.reach) else {
            return unmoved;
        };
        let after = balance::imbalance(&balance::work_per_slab(&hist, z0, length, &bounds));
        if after >= before {
            return unmoved;
        }
        self.slabs.bounds = bounds;
        let saved = self.saved_histories();
        self.rebuild_with(saved, true, Reorder::Keep);
        BalanceCheck {
            before,
            after,
            bound,
        }
    }

    /// Recompute the forces of the current state (after changing gravity, walls or scale).
    /// The ghosts are refreshed first: they must carry their owners' current velocities, not
    /// the predicted ones of the last step, or a pair across a slab face would be evaluated
    /// with different inputs on its two sides.
    pub fn refresh_forces(&mut self) {
        self.update_ghosts_during_wall_forces(false, None);
        self.pair_forces(false);
    }

    /// Mean over axial slices (of width about `width`) of the highest particle centre.
    pub fn bed_top(&self, width: f64) -> f64 {
        let n = ((self.slabs.length / width).floor() as usize).max(1);
        let z0 = -0.5 * self.slabs.length;
        let mut top = vec![f64::NEG_INFINITY; n];
        for i in self.mobile() {
            let k = (((self.p.x[i][2] - z0) / self.slabs.length * n as f64) as usize).min(n - 1);
            top[k] = top[k].max(self.p.x[i][1]);
        }
        self.comm.max_f64_all(&mut top);
        let filled: Vec<f64> = top.into_iter().filter(|t| t.is_finite()).collect();
        filled.iter().sum::<f64>() / filled.len().max(1) as f64
    }

    /// This rank's verdict on the state: non-finite values, particles outside the drum, or an
    /// overlap above `max_overlap` of the smaller diameter, with the particle, the step and
    /// the likely cause. `limit` names where the overlap limit comes from, for the message.
    /// Every rank checks its own particles.
    pub fn health(&self, max_overlap: f64, limit: &str) -> Result<(), String> {
        let cause = "the time step is probably too large for the contact stiffness or damping \
                     (see `tumbler check`), or the particles were started too fast";
        if let Some(fault) = &self.fault {
            return Err(fault.clone());
        }
        for i in self.mobile() {
            let (x, v, w) = (self.p.x[i], self.p.v[i], self.p.w[i]);
            let describe = |what: &str| {
                format!(
                    "run stopped at step {}: particle {} (species {}) at ({:.6e}, {:.6e}, {:.6e}) {what}; {cause}",
                    self.step, self.p.id[i], self.p.species[i], x[0], x[1], x[2]
                )
            };
            if x.iter().chain(&v).chain(&w).any(|c| !c.is_finite()) {
                return Err(describe("has a non-finite position, velocity or spin"));
            }
            if !self.walls.inside(x, 0.0) {
                return Err(describe("has left the drum"));
            }
        }
        let (overlap, a, b) = self.worst_overlap();
        if overlap > max_overlap {
            return Err(format!(
                "run stopped at step {}: particles {a} and {b} overlap by {:.1} % of the smaller diameter \
                 ({limit} is {:.1} %); {cause}",
                self.step,
                100.0 * overlap,
                100.0 * max_overlap
            ));
        }
        Ok(())
    }

    /// Ids of this rank's owned mobile particles that touch a wall now but are not in the list
    /// of those near a wall (`NeighborList::near_walls`, the only ones the wall pass tests):
    /// none, if that list holds until the next build (tests check it step by step).
    pub fn wall_contacts_unlisted(&self) -> Vec<u64> {
        let near: std::collections::HashSet<u32> = self.nl.near_walls.iter().copied().collect();
        self.mobile()
            .filter(|&i| !near.contains(&(i as u32)))
            .filter(|&i| {
                let reach = self.law.wall_reach(self.p.diameter[i] * self.scale);
                self.walls.touches(self.p.x[i], reach)
            })
            .map(|i| self.p.id[i])
            .collect()
    }

    /// This rank's pair list (local indices, lower id first) and the axial period, for
    /// measurements that read the contacts without computing forces (`engine::thermo`).
    pub fn pair_list(&self) -> (&[(u32, u32)], Option<f64>) {
        (&self.nl.pairs, self.period())
    }

    /// The largest overlap of a listed pair, relative to the smaller diameter (the contact
    /// diameter being `(d_a + d_b)/2` in both families), and that pair's ids.
    fn worst_overlap(&self) -> (f64, u64, u64) {
        let period = self.period();
        let mut worst = (0.0, 0, 0);
        for &(a, b) in &self.nl.pairs {
            let (a, b) = (a as usize, b as usize);
            let (xa, xb) = (self.p.x[a], self.p.x[b]);
            let mut dz = xa[2] - xb[2];
            if let Some(l) = period {
                dz = min_image(dz, l);
            }
            let r2 = (xa[0] - xb[0]).powi(2) + (xa[1] - xb[1]).powi(2) + dz * dz;
            let (da, db) = (
                self.p.diameter[a] * self.scale,
                self.p.diameter[b] * self.scale,
            );
            let touch = 0.5 * (da + db);
            if r2 < touch * touch {
                let overlap = (touch - r2.sqrt()) / da.min(db);
                if overlap > worst.0 {
                    worst = (overlap, self.p.id[a], self.p.id[b]);
                }
            }
        }
        worst
    }

    /// Owned particles, ghosts and the bytes of one ghost refresh on each rank, the smallest
    /// and the largest over the ranks (every rank calls this together): how evenly the
    /// decomposition shares the particles and what the halo costs per step.
    pub fn spread(&self) -> [(f64, f64); 3] {
        let mut v = [
            self.p.n_owned as f64,
            self.halo.ghosts() as f64,
            self.halo.update_bytes() as f64,
        ];
        let mut neg = v.map(|x| -x);
        self.comm.max_f64_all(&mut v);
        self.comm.max_f64_all(&mut neg);
        [0, 1, 2].map(|k| (-neg[k], v[k]))
    }

    /// This rank's mobile particles (the owned ones not fixed to the drum): those the files
    /// hold.
    fn mobile(&self) -> impl Iterator<Item = usize> + Clone + '_ {
        (0..self.p.n_owned).filter(|&i| !is_fixed(self.p.species[i]))
    }

    /// Total number of mobile particles over all ranks.
    pub fn global_count(&self) -> u64 {
        self.comm.sum_u64(self.mobile().count() as u64)
    }

    /// Which rank keeps which ids in the files' id order ([`Sim::particles_by_id`]): a
    /// histogram of the mobile ids (summed over ranks) cut into shares of about N/P
    /// particles. Returns the histogram's bin width in ids and each bin's rank.
    fn id_shares(&self) -> (u64, Vec<usize>) {
        let size = self.comm.size();
        // ids are below 2^53 (they travel as f64), so the maximum is exact
        let top = self.comm.max_f64(
            self.mobile()
                .map(|i| self.p.id[i])
                .max()
                .map_or(0.0, |m| m as f64),
        ) as u64;
        let bins = (16 * size).min(1 << 20) as u64;
        let width = (top / bins + 1).max(1);
        let mut hist = vec![0u64; bins as usize];
        for i in self.mobile() {
            hist[((self.p.id[i] / width) as usize).min(bins as usize - 1)] += 1;
        }
        self.comm.sum_u64_all(&mut hist);
        let n: u64 = hist.iter().sum();
        let mut before = 0u64;
        let owner = hist
            .iter()
            .map(|&c| {
                let r = (before as u128 * size as u128 / n.max(1) as u128) as usize;
                before += c;
                r.min(size - 1)
            })
            .collect();
        (width, owner)
    }

    /// Send every item of `items` (`words` values each, written by `pack`) to the rank of
    /// its id's share (`id_shares`); what this rank receives, one message per rank. The
    /// items are counted first and packed straight into messages of their exact size, so
    /// that the exchange holds each record once on the sending side (and this rank's own
    /// message is handed back without a copy).
    fn to_shares<T: Copy>(
        &self,
        items: impl Iterator<Item = T> + Clone,
        words: usize,
        id: impl Fn(T) -> u64,
        pack: impl Fn(T, &mut Vec<f64>),
    ) -> Vec<Vec<f64>> {
        let (width, owner) = self.id_shares();
        let rank_of = |x: T| owner[((id(x) / width) as usize).min(owner.len() - 1)];
        let mut counts = vec![0usize; self.comm.size()];
        for x in items.clone() {
            counts[rank_of(x)] += words;
        }
        let mut to: Vec<Vec<f64>> = counts.iter().map(|&c| Vec::with_capacity(c)).collect();
        for x in items {
            pack(x, &mut to[rank_of(x)]);
        }
        self.comm.all_to_all(to)
    }

    /// This rank's share of every mobile particle's state, sorted by id, the ranks' shares
    /// following in increasing order of id (about N/P each): what each rank writes of a
    /// file's particles (all ranks call this together).
    pub fn particles_by_id(&self) -> Records {
        let words = self.p.packed_words();
        let mut mine = self.to_shares(
            self.mobile(),
            words,
            |i| self.p.id[i],
            |i, m| self.p.pack(i, m),
        );
        // kept as the records received: the largest message grows (a mapped block, moved
        // without a copy) by the others, each freed once appended
        let total = mine.iter().map(Vec::len).sum::<usize>();
        let largest = (0..mine.len()).max_by_key(|&r| mine[r].len()).unwrap_or(0);
        let mut data = mine
            .get_mut(largest)
            .map(std::mem::take)
            .unwrap_or_default();
        data.reserve_exact(total - data.len());
        for m in mine {
            data.extend_from_slice(&m);
        }
        let mut states = Records::new(self.p.hist_words, data);
        states.sort_by_id();
        states
    }

    /// This rank's share of the contact histories, sorted by ids, each once (a contact
    /// across a slab face is held, identically, by both ranks), a contact in the share of
    /// its lower id, the shares as [`Sim::particles_by_id`]'s (all ranks call this
    /// together). Empty for a law without histories.
    pub fn histories_by_ids(&self) -> SavedHistory {
        let hist_words = self.p.hist_words;
        let rec = record_words(hist_words);
        let saved = self.saved_histories();
        let mine = self.to_shares(
            saved.iter(),
            rec,
            |h| h.a,
            |h, m| push_record(m, h, hist_words),
        );
        drop(saved);
        let mut out: SavedHistory = Vec::with_capacity(mine.iter().map(|m| m.len() / rec).sum());
        for m in mine {
            out.extend(m.chunks_exact(rec).map(|r| read_record(r, hist_words)));
        }
        out.sort_unstable_by_key(SavedContact::ids);
        out.dedup_by_key(|x| x.ids());
        out
    }

    /// This rank's particles that a file holds (the mobile ones) and its contacts with a
    /// history: upper bounds of its rows of a checkpoint (a contact across a slab face is
    /// counted by both ranks).
    pub fn checkpoint_rows(&self) -> [u64; 2] {
        let mobile = self.mobile().count();
        let contacts = if self.law.has_history() {
            self.nl.history_count()
        } else {
            0
        };
        [mobile as u64, contacts as u64]
    }
}

/// What a rebuild does about the order keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reorder {
    /// Nothing: the keys are those of the last sort.
    Keep,
    /// A sort: once migrated, the owned particles get the keys of where they are now and
    /// their storage follows them; the ghosts bring their owners' new keys, and the saved
    /// histories (saved with the old ones, which both sides of a slab face agree on, unlike
    /// a ghost's new key before its owner sent it) are then given the new keys.
    Sort,
    /// The saved histories come from a checkpoint, without their particles' keys: they are
    /// given them once the halo is built (and the storage is sorted, as the particles come
    /// in the order of ids).
    KeysOfSaved,
}

/// Give each saved history the keys of its particles as `p` holds them, and sort it into the
/// list's order. A contact of which a particle is not here keeps key 0 for it: it has no
/// pair in the list and is dropped.
fn give_keys(p: &Particles, saved: &mut SavedHistory) {
    let mut keys: Vec<(u64, u64)> = p.id.iter().copied().zip(p.key.iter().copied()).collect();
    keys.sort_unstable();
    keys.dedup_by_key(|x| x.0);
    let key_of = |id: u64| {
        keys.binary_search_by_key(&id, |x| x.0)
            .map_or(0, |k| keys[k].1)
    };
    for c in saved.iter_mut() {
        c.key_a = key_of(c.a);
        c.key_b = key_of(c.b);
    }
    sort_saved(saved);
}

/// Whether the lists must be rebuilt after the largest displacement since the last build
/// came to `moved` (the maximum over the ranks, so that every rank decides alike): beyond a
/// hair below half the `skin` (so that pairs listed at exactly the list range on one rank
/// and not on another, from last-bit differences of periodic images, never touch), or when
/// the particles are to be sorted. Never for a non-finite displacement: the run stops
/// instead, and nothing is rebuilt from bad coordinates.
fn rebuild_due(moved: f64, skin: f64, sort: bool) -> bool {
    moved.is_finite() && (2.0 * moved > skin * (1.0 - 1e-9) || sort)
}
