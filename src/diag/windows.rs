//! The windowed diagnostics of a run: at every sample the surface angle is measured, the
//! surface frame built from it, and the particles binned for the per-slice fluxes and the
//! fields; at the end of a window the sums are reduced to the ranks that hold them (the
//! per-slice sums in even blocks of slices, the fields on rank 0) and turned into means.

use super::fields::{self, FieldWindow};
use super::grid::{BinnedSums, Grid, Quantities, Scales, Split};
use super::slices::{self, SliceWindow};
use super::surface::{Frame, SurfaceAngles, SurfaceGauge};
use super::AxialBins;
use crate::case::Case;
use crate::comm::Comm;
use crate::particles::Particles;

/// The angles of repose of a window: per-slice and whole-drum sums over its samples.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AngleSums {
    /// Per slice: sum of finite angles.
    pub slice_sum: Vec<f64>,
    /// Per slice: samples with a finite angle.
    pub slice_n: Vec<u64>,
    /// Whole drum: sum of finite angles.
    pub drum_sum: f64,
    /// Whole drum: samples with a finite angle.
    pub drum_n: u64,
}

impl AngleSums {
    fn new(nz: usize) -> Self {
        AngleSums {
            slice_sum: vec![0.0; nz],
            slice_n: vec![0; nz],
            ..Default::default()
        }
    }

    fn add(&mut self, a: &SurfaceAngles) {
        for (k, &x) in a.slice.iter().enumerate() {
            if x.is_finite() {
                self.slice_sum[k] += x;
                self.slice_n[k] += 1;
            }
        }
        if a.drum.is_finite() {
            self.drum_sum += a.drum;
            self.drum_n += 1;
        }
    }

    fn clear(&mut self) {
        *self = AngleSums::new(self.slice_sum.len());
    }

    fn means(&self) -> (Vec<f64>, f64) {
        let mean = |s: f64, n: u64| if n > 0 { s / n as f64 } else { f64::NAN };
        (
            self.slice_sum
                .iter()
                .zip(&self.slice_n)
                .map(|(&s, &n)| mean(s, n))
                .collect(),
            mean(self.drum_sum, self.drum_n),
        )
    }
}

/// One window of per-slice diagnostics with its angles.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceRecord {
    /// Fluxes, concentrations and diffusivity.
    pub slices: SliceWindow,
    /// Mean angle of repose per slice, degrees.
    pub angle: Vec<f64>,
    /// Mean whole-drum angle, degrees.
    pub angle_drum: f64,
}

/// Accumulators of the windowed diagnostics.
#[derive(Debug, Clone)]
pub struct Windows {
    gauge: SurfaceGauge,
    fixed_angle: Option<f64>,
    omega: f64,
    periodic: bool,
    /// Per-slice flux sums of the current window.
    pub slices: BinnedSums,
    /// Field sums of the current field window.
    pub fields: BinnedSums,
    /// Angle sums of the current window (the same on every rank).
    pub angles: AngleSums,
}

impl Windows {
    /// Accumulators for `case`, on the axial slices of `axial`.
    pub fn new(case: &Case, axial: &AxialBins) -> Self {
        let radius = 0.5 * case.drum.diameter;
        let length = case.drum.axial_length();
        let d_max = case.d_max();
        let omega = case.drum.omega;
        let g = &case.diagnostics;
        let scales = Scales {
            length: radius,
            volume: d_max * d_max * d_max,
            velocity: super::grid::velocity_scale(case),
        };
        let ns = case.species.len();
        let [nx, ny, nzf] = case.field_grid();
        Windows {
            gauge: SurfaceGauge::new(axial.nz, axial.z0, axial.width, radius, d_max, omega),
            fixed_angle: g.surface_angle,
            omega,
            periodic: case.drum.periodic(),
            slices: BinnedSums::new(
                Grid::new([nx, ny, axial.nz], radius, axial.z0, length),
                ns,
                Quantities::Flux,
                scales,
                Split::Even,
            ),
            fields: BinnedSums::new(
                Grid::new([nx, ny, nzf], radius, -0.5 * length, length),
                ns,
                Quantities::Fields,
                scales,
                Split::Root,
            ),
            angles: AngleSums::new(axial.nz),
        }
    }

    /// Measure the surface of this rank's particles together with the other ranks.
    pub fn measure(&self, p: &Particles, comm: &dyn Comm) -> SurfaceAngles {
        let mut tops = self.gauge.local_tops(p);
        comm.max_f64_all(&mut tops);
        self.gauge.angles(&tops)
    }

    /// Take one sample: measure the angles, build the frame, bin the particles.
    pub fn sample(&mut self, p: &Particles, comm: &dyn Comm) {
        let angles = self.measure(p, comm);
        let theta = self.fixed_angle.unwrap_or(if angles.drum.is_finite() {
            angles.drum
        } else {
            0.0
        });
        let frame = Frame::new(theta, self.omega);
        self.angles.add(&angles);
        self.slices.add(p, &frame, self.omega);
        self.fields.add(p, &frame, self.omega);
    }

    /// Hold this rank's blocks of the reduced sums (rank `rank` of `size`) from the start.
    pub fn hold_own(&mut self, rank: usize, size: usize) {
        self.slices.hold_own(rank, size);
        self.fields.hold_own(rank, size);
    }

    /// End the per-slice window: reduce each block of slices to the rank that holds it,
    /// which derives what each of its slices needs of its own bins; gather those per-slice
    /// records on rank 0, which adds the gradients (`None` elsewhere); start afresh.
    pub fn flush_slices(&mut self, comm: &dyn Comm) -> Option<SliceRecord> {
        self.slices.reduce(comm);
        let records = comm.gather_f64(&slices::slice_records(&self.slices));
        let out = records.map(|records| {
            let (angle, angle_drum) = self.angles.means();
            SliceRecord {
                slices: slices::assemble(&self.slices, &records, self.periodic),
                angle,
                angle_drum,
            }
        });
        self.slices.clear();
        self.angles.clear();
        out
    }

    /// End the field window: reduce, derive on rank 0 (`None` elsewhere), start afresh.
    pub fn flush_fields(&mut self, comm: &dyn Comm) -> Option<FieldWindow> {
        self.fields.reduce(comm);
        let out = (comm.rank() == 0).then(|| fields::derive(&self.fields, self.omega));
        self.fields.clear();
        out
    }

    /// Reduce the partial windows into the ranks' blocks for a checkpoint (each rank then
    /// holds its block whole and nothing outside it, so nothing is counted twice when the
    /// run goes on).
    pub fn consolidate(&mut self, comm: &dyn Comm) {
        self.slices.reduce(comm);
        self.fields.reduce(comm);
    }
}
