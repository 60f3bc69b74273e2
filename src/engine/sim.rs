//! The simulation state of one rank and the step loop.

use super::forces::{pair_forces, wall_and_body_forces};
use super::halo::{self, Halo};
use super::neighbor::{Grid, NeighborList};
use super::slabs::Slabs;
use super::timers::{Phase, Timers};
use crate::case::{Case, Ends};
use crate::comm::Comm;
use crate::particles::{ParticleState, Particles};
use crate::physics::integrate::{drift, half_kick};
use crate::physics::{rapaport, DrumWalls, Materials};

/// Why a decomposition cannot be used.
#[derive(Debug, Clone, PartialEq)]
pub struct DecompositionError(pub String);

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
    /// Friction tables and material constants.
    pub mat: Materials,
    /// The drum's walls.
    pub walls: DrumWalls,
    /// The slab decomposition.
    pub slabs: Slabs,
    /// Owned particles, then ghosts.
    pub p: Particles,
    halo: Halo,
    nl: NeighborList,
    /// Steps taken since time zero.
    pub step: u64,
    /// Interaction range of the largest pair plus the skin: the halo width and cell size.
    pub reach: f64,
    /// Time per phase.
    pub timers: Timers,
    /// Neighbour-list rebuilds so far.
    pub rebuilds: u64,
    /// Particles this rank sent to neighbours by migration so far.
    pub migrated: u64,
    /// Contacts in the last force pass.
    pub contacts: usize,
}

impl<'c> Sim<'c> {
    /// Set up a rank from the global initial state (every rank sees all of it and keeps the
    /// particles in its own slab), and compute the initial forces.
    pub fn new(
        case: &Case,
        comm: &'c dyn Comm,
        initial: &[ParticleState],
    ) -> Result<Self, DecompositionError> {
        let mat = Materials::new(case);
        let periodic = case.drum.ends == Ends::Periodic;
        let slabs = Slabs::uniform(comm.size(), case.drum.length, periodic);
        let d_max = case.species.iter().map(|s| s.diameter).fold(0.0, f64::max);
        let reach = rapaport::cutoff(d_max) + case.run.skin;
        if slabs.min_width() < reach {
            return Err(DecompositionError(format!(
                "{} ranks cut the drum (length {}) into slabs {:.3} long, thinner than the \
                 interaction range + skin {:.3}; use at most {} ranks",
                comm.size(),
                case.drum.length,
                slabs.min_width(),
                reach,
                ((case.drum.length / reach).floor() as usize).max(1)
            )));
        }
        let walls = DrumWalls {
            radius: 0.5 * case.drum.diameter,
            half_length: 0.5 * case.drum.length,
            capped: !periodic,
            omega: case.drum.omega,
            wall_diameter: mat.wall_diameter,
            gamma_n: mat.gamma_n,
        };
        let mut p = Particles::default();
        let me = comm.rank();
        for s in initial.iter().filter(|s| slabs.owner(s.x[2]) == me) {
            p.push_owned(s, &mat);
        }
        let mut sim = Sim {
            comm,
            case: case.clone(),
            mat,
            walls,
            slabs,
            p,
            halo: Halo::default(),
            nl: NeighborList::default(),
            step: 0,
            reach,
            timers: Timers::default(),
            rebuilds: 0,
            migrated: 0,
            contacts: 0,
        };
        sim.rebuild();
        sim.forces();
        Ok(sim)
    }

    fn period(&self) -> Option<f64> {
        self.slabs.periodic.then_some(self.case.drum.length)
    }

    /// Time since the drum started turning.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.case.run.dt
    }

    /// Drum rotations completed so far.
    pub fn rotations(&self) -> f64 {
        self.time() * self.case.drum.omega.abs() / (2.0 * std::f64::consts::PI)
    }

    /// The communicator this rank uses.
    pub fn comm(&self) -> &'c dyn Comm {
        self.comm
    }

    /// Advance one time step (velocity Verlet):
    /// half kick, drift, halo (rebuilt or refreshed), forces, half kick.
    pub fn step(&mut self) {
        let dt = self.case.run.dt;
        let period = self.period();
        let n = self.p.n_owned;
        let p = &mut self.p;
        self.timers.time(Phase::Integrate, || {
            half_kick(
                n,
                0.5 * dt,
                &mut p.v,
                &mut p.w,
                &p.f,
                &p.t,
                &p.inv_mass,
                &p.inv_inertia,
            );
            drift(n, dt, &mut p.x, &p.v, period);
        });
        let moved = self.timers.time(Phase::Comm, || {
            self.comm.max_f64(self.nl.max_displacement(&self.p, period))
        });
        if 2.0 * moved > self.case.run.skin {
            self.rebuild();
        } else {
            let (p, halo, slabs, comm) = (&mut self.p, &self.halo, &self.slabs, self.comm);
            self.timers
                .time(Phase::Comm, || halo::update_ghosts(p, halo, slabs, comm));
        }
        self.forces();
        // Migration may have changed the owned count.
        let (n, p) = (self.p.n_owned, &mut self.p);
        self.timers.time(Phase::Integrate, || {
            half_kick(
                n,
                0.5 * dt,
                &mut p.v,
                &mut p.w,
                &p.f,
                &p.t,
                &p.inv_mass,
                &p.inv_inertia,
            );
        });
        self.step += 1;
    }

    /// Migrate particles that left the slab, rebuild the halo and the pair list.
    fn rebuild(&mut self) {
        let (p, slabs, comm, mat, reach) =
            (&mut self.p, &self.slabs, self.comm, &self.mat, self.reach);
        let (sent, halo) = self.timers.time(Phase::Comm, || {
            p.clear_ghosts();
            let sent = halo::migrate(p, slabs, comm, mat);
            (sent, halo::borders(p, slabs, comm, mat, reach))
        });
        self.migrated += sent as u64;
        self.halo = halo;
        let (lo, hi) = self.slabs.range(self.comm.rank());
        let grid = Grid::new(
            self.walls.radius,
            lo - self.reach,
            hi + self.reach,
            self.reach,
        );
        let (nl, p, skin) = (&mut self.nl, &self.p, self.case.run.skin);
        self.timers
            .time(Phase::Neighbor, || nl.build(p, &grid, skin));
        self.rebuilds += 1;
    }

    fn forces(&mut self) {
        let period = self.period();
        let (p, nl, mat) = (&mut self.p, &self.nl, &self.mat);
        let stats = self
            .timers
            .time(Phase::Pairs, || pair_forces(p, nl, mat, period));
        self.contacts = stats.contacts;
        let (walls, g) = (&self.walls, self.case.model.gravity);
        self.timers
            .time(Phase::Walls, || wall_and_body_forces(p, walls, mat, g));
    }

    /// Total number of particles over all ranks.
    pub fn global_count(&self) -> u64 {
        self.comm.sum_u64(self.p.n_owned as u64)
    }

    /// Every particle's state, sorted by id, on rank 0 (`None` elsewhere).
    pub fn gather_sorted(&self) -> Option<Vec<ParticleState>> {
        let mut buf = Vec::with_capacity(self.p.n_owned * crate::particles::PACKED_WORDS);
        for i in 0..self.p.n_owned {
            self.p.pack(i, &mut buf);
        }
        let all = self.comm.gather_f64(&buf)?;
        let mut states: Vec<ParticleState> = all
            .chunks_exact(crate::particles::PACKED_WORDS)
            .map(crate::particles::unpack)
            .collect();
        states.sort_by_key(|s| s.id);
        Some(states)
    }
}
