//! The figures the validation checks read from a run's file: the big species' axial
//! profile late in the run, its band structure and a segregation index, the share of the
//! big species near the ends and at the equator, the axial flow in the free-surface layer
//! next to each end wall, and the angle of repose of rich and poor slices.

use crate::diag::bands::{find_bands, Band, BandRule};
use crate::inspect::{effective_rule, BandsOptions, InspectError, RunReader, Window};

/// The big species' volume fraction along the axis at every axial sample.
pub struct AxialSeries {
    /// Sample times, in rotations.
    pub rotations: Vec<f64>,
    /// `big[t][k]`: the big species' volume fraction in slice `k` at sample `t` (NaN if empty).
    pub big: Vec<Vec<f64>>,
    /// The band rule the run used (`/axial/bands` attributes), or the defaults.
    pub rule: BandRule,
}

impl AxialSeries {
    /// Read `/axial` of the file open in `reader`.
    pub fn read(reader: &RunReader) -> Result<Self, InspectError> {
        let rotations = reader.vector("axial/rotations")?;
        let z = reader.centres("axial/z")?;
        let vf = reader.array("axial/volume_fraction", &["T", "S", "Z"])?;
        let species = reader.big_species()?;
        let s = vf.shape().to_vec();
        reader.check_len("axial/volume_fraction", s[0], rotations.len(), "samples")?;
        reader.check_len("axial/volume_fraction", s[2], z.len(), "slices")?;
        if species >= s[1] {
            return Err(reader.layout("axial/volume_fraction", "lacks the big species"));
        }
        let big = (0..s[0])
            .map(|t| (0..s[2]).map(|k| vf[[t, species, k]]).collect())
            .collect();
        let rule = effective_rule(reader, &BandsOptions::default())?;
        Ok(AxialSeries {
            rotations,
            big,
            rule,
        })
    }

    /// The run's length in rotations (the last sample).
    pub fn end(&self) -> f64 {
        self.rotations.last().copied().unwrap_or(0.0)
    }

    /// The profile averaged over the samples in the last `rotations` of the run (at least
    /// the last sample); a slice empty in every one of them is NaN.
    pub fn late_profile(&self, rotations: f64) -> Vec<f64> {
        let end = self.end();
        let p = self.profile_between(end - rotations, end);
        if p.is_empty() {
            self.big.last().cloned().unwrap_or_default()
        } else {
            p
        }
    }

    /// The profile averaged over the samples taken in `(from, to]` rotations (empty if
    /// there are none).
    pub fn profile_between(&self, from: f64, to: f64) -> Vec<f64> {
        let picked: Vec<&Vec<f64>> = self
            .rotations
            .iter()
            .zip(&self.big)
            .filter(|(r, _)| **r > from + 1e-9 && **r <= to + 1e-9)
            .map(|(_, p)| p)
            .collect();
        if picked.is_empty() {
            Vec::new()
        } else {
            mean_profile(&picked)
        }
    }

    /// The profile at the first sample.
    pub fn initial_profile(&self) -> Vec<f64> {
        self.big.first().cloned().unwrap_or_default()
    }

    /// The segregation index ([`segregation_index`]) of every sample.
    pub fn segregation(&self) -> Vec<f64> {
        self.big.iter().map(|p| segregation_index(p)).collect()
    }

    /// The bands of `profile` by the run's rule.
    pub fn bands(&self, profile: &[f64]) -> Vec<Band> {
        find_bands(profile, &self.rule)
    }

    /// The first sample time with at least `n` bands (each sample's own profile).
    pub fn first_with_bands(&self, n: usize) -> Option<f64> {
        self.rotations
            .iter()
            .zip(&self.big)
            .find(|(_, p)| find_bands(p, &self.rule).len() >= n)
            .map(|(r, _)| *r)
    }
}

/// Slice-wise mean of `profiles`, skipping NaN; NaN where every profile is NaN.
pub fn mean_profile(profiles: &[&Vec<f64>]) -> Vec<f64> {
    let n = profiles.first().map_or(0, |p| p.len());
    (0..n)
        .map(|k| {
            let vals: Vec<f64> = profiles
                .iter()
                .map(|p| p[k])
                .filter(|c| c.is_finite())
                .collect();
            if vals.is_empty() {
                f64::NAN
            } else {
                vals.iter().sum::<f64>() / vals.len() as f64
            }
        })
        .collect()
}

/// How far a profile is from mixed: the standard deviation of the volume fraction over the
/// occupied slices divided by `sqrt(m (1 - m))`, `m` its mean. 0 for a uniform profile, 1
/// when every slice holds one species only.
pub fn segregation_index(profile: &[f64]) -> f64 {
    let c: Vec<f64> = profile.iter().copied().filter(|c| c.is_finite()).collect();
    if c.is_empty() {
        return 0.0;
    }
    let m = c.iter().sum::<f64>() / c.len() as f64;
    let var = c.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / c.len() as f64;
    let scale = (m * (1.0 - m)).sqrt();
    if scale > 0.0 {
        var.sqrt() / scale
    } else {
        0.0
    }
}

/// Mean of the finite entries of `values` (NaN if none).
pub fn finite_mean(values: impl IntoIterator<Item = f64>) -> f64 {
    let (sum, n) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        sum / n as f64
    }
}

/// The occupied slices of `profile` (finite entries) split into thirds along the axis:
/// the mean volume fraction of the low third, the middle third and the high third.
pub fn thirds(profile: &[f64]) -> [f64; 3] {
    let occupied: Vec<f64> = profile.iter().copied().filter(|c| c.is_finite()).collect();
    let n = occupied.len();
    let cut = |k: usize| (k * n + 1) / 3;
    let part = |a: usize, b: usize| finite_mean(occupied[a..b].iter().copied());
    [part(0, cut(1)), part(cut(1), cut(2)), part(cut(2), n)]
}

/// Mean of the first `n` and of the last `n` occupied slices of `profile`, and of the middle
/// half of the occupied slices.
pub fn ends_and_centre(profile: &[f64], n: usize) -> (f64, f64, f64) {
    let occupied: Vec<f64> = profile.iter().copied().filter(|c| c.is_finite()).collect();
    let m = occupied.len();
    let n = n.min(m / 2);
    (
        finite_mean(occupied[..n].iter().copied()),
        finite_mean(occupied[m - n..].iter().copied()),
        finite_mean(occupied[m / 4..m - m / 4].iter().copied()),
    )
}

/// The bin of centres `y` whose upper edge is the surface height `top` (`/fields/surface`,
/// NaN where a column has no surface).
fn top_bin(y: &[f64], top: f64) -> Option<usize> {
    let dy = if y.len() > 1 { y[1] - y[0] } else { 1.0 };
    y.iter()
        .position(|&yj| (yj + 0.5 * dy - top).abs() < 0.25 * dy)
}

/// Axial velocity in the free-surface layer of one field window, next to the two ends.
#[derive(Debug, Clone, Copy)]
pub struct EndFlow {
    /// Mean `w` at the low end (`z = -L/2`): upstream (`x < 0`) and downstream (`x > 0`).
    pub low: [f64; 2],
    /// The same at the high end (`z = +L/2`).
    pub high: [f64; 2],
    /// The same over the middle of the drum.
    pub centre: [f64; 2],
    /// The streamwise surface velocity at the centre, `u0`.
    pub u0: f64,
}

/// [`EndFlow`] of field window `window`: the mean axial velocity `w` of the surface bin (the
/// top bin, whose upper edge is `/fields/surface`) of every flowing column (finite
/// `/fields/boundary`), over the `slices` field slices nearest each end and the `slices`
/// nearest the middle, upstream and downstream separately.
pub fn end_flow(reader: &RunReader, window: usize, slices: usize) -> Result<EndFlow, InspectError> {
    let x = reader.centres("fields/x")?;
    let y = reader.centres("fields/y")?;
    let z = reader.centres("fields/z")?;
    let vel = reader.array("fields/velocity", &["F", "3", "X", "Y", "ZF"])?;
    let surface = reader.array("fields/surface", &["F", "X", "ZF"])?;
    let boundary = reader.array("fields/boundary", &["F", "X", "ZF"])?;
    let u0 = reader.vector("fields/u0")?;
    if window >= u0.len() {
        return Err(reader.layout("fields/u0", format!("has no window {window}")));
    }
    let nz = z.len();
    let slices = slices.min(nz / 2).max(1);
    let mean_w = |ks: &[usize], upstream: bool| {
        let mut vals = Vec::new();
        for &k in ks {
            for (i, &xi) in x.iter().enumerate() {
                if (xi < 0.0) != upstream || !boundary[[window, i, k]].is_finite() {
                    continue;
                }
                if let Some(j) = top_bin(&y, surface[[window, i, k]]) {
                    vals.push(vel[[window, 2, i, j, k]]);
                }
            }
        }
        finite_mean(vals)
    };
    let both = |ks: &[usize]| [mean_w(ks, true), mean_w(ks, false)];
    let low: Vec<usize> = (0..slices).collect();
    let high: Vec<usize> = (nz - slices..nz).collect();
    let mid0 = (nz - slices) / 2;
    let centre: Vec<usize> = (mid0..mid0 + slices).collect();
    Ok(EndFlow {
        low: both(&low),
        high: both(&high),
        centre: both(&centre),
        u0: u0[window],
    })
}

/// Dynamic angle of repose against composition in one `/slices` window.
#[derive(Debug, Clone)]
pub struct AngleByComposition {
    /// The window measured: the last whole one.
    pub window: Window,
    /// The third of the slices richest in the big species: its mean share and mean angle
    /// (degrees).
    pub rich: [f64; 2],
    /// The third poorest in it: the same.
    pub poor: [f64; 2],
}

/// [`AngleByComposition`] of the last whole window of `/slices` (a run's final window can be
/// a fragment, and a fragment's angles rest on a sample or two): the slices with both a
/// share and an angle, sorted by the big species' share (`/slices/concentration`); the mean
/// share and angle (`/slices/angle`) of the richest third and of the poorest third.
pub fn angle_by_composition(
    reader: &RunReader,
    big: usize,
) -> Result<AngleByComposition, InspectError> {
    let starts = reader.vector("slices/rotations_start")?;
    let ends = reader.vector("slices/rotations_end")?;
    let length: Vec<f64> = starts.iter().zip(&ends).map(|(s, e)| e - s).collect();
    let longest = length.iter().copied().fold(0.0, f64::max);
    let index = length
        .iter()
        .rposition(|&l| l >= 0.99 * longest)
        .ok_or_else(|| reader.layout("slices/rotations_start", "holds no window"))?;
    let window = reader.window("slices", Some(index))?;
    let share = reader.array("slices/concentration", &["W", "S", "Z"])?;
    let angle = reader.array("slices/angle", &["W", "Z"])?;
    if big >= share.shape()[1] || share.shape()[2] != angle.shape()[1] {
        return Err(reader.layout("slices/concentration", "does not match /slices/angle"));
    }
    let mut slices: Vec<[f64; 2]> = (0..angle.shape()[1])
        .map(|k| [share[[index, big, k]], angle[[index, k]]])
        .filter(|s| s[0].is_finite() && s[1].is_finite())
        .collect();
    slices.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let third = (slices.len() / 3).max(1);
    let mean = |part: &[[f64; 2]]| {
        [
            finite_mean(part.iter().map(|s| s[0])),
            finite_mean(part.iter().map(|s| s[1])),
        ]
    };
    Ok(AngleByComposition {
        rich: mean(&slices[slices.len().saturating_sub(third)..]),
        poor: mean(&slices[..third.min(slices.len())]),
        window,
    })
}

/// The big species' share of the particle volume in the free-surface layer along the axis,
/// for field window `window`: in every column `(x, z)` with a surface, the top bin (whose
/// upper edge is `/fields/surface`); per field slice, the big species' volume over all
/// species' volume in those bins (NaN where a slice has no surface). This is the pattern
/// seen from above, as thesis ch. 5 reports it.
pub fn surface_share(
    reader: &RunReader,
    window: usize,
    big: usize,
) -> Result<Vec<f64>, InspectError> {
    let x = reader.centres("fields/x")?;
    let y = reader.centres("fields/y")?;
    let z = reader.centres("fields/z")?;
    let vf = reader.array("fields/volume_fraction", &["F", "S", "X", "Y", "ZF"])?;
    let surface = reader.array("fields/surface", &["F", "X", "ZF"])?;
    if window >= vf.shape()[0] || big >= vf.shape()[1] {
        return Err(reader.layout("fields/volume_fraction", "lacks the window or species"));
    }
    let species = vf.shape()[1];
    Ok((0..z.len())
        .map(|k| {
            let (mut b, mut all) = (0.0, 0.0);
            for i in 0..x.len() {
                if let Some(j) = top_bin(&y, surface[[window, i, k]]) {
                    b += vf[[window, big, i, j, k]];
                    all += (0..species).map(|s| vf[[window, s, i, j, k]]).sum::<f64>();
                }
            }
            if all > 0.0 {
                b / all
            } else {
                f64::NAN
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segregation_index_is_zero_when_mixed_and_one_when_pure() {
        assert_eq!(segregation_index(&[0.5; 8]), 0.0);
        let pure = [1.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0];
        assert!((segregation_index(&pure) - 1.0).abs() < 1e-12);
        // empty slices are ignored
        let gaps = [1.0, f64::NAN, 0.0, 1.0, 0.0, f64::NAN];
        assert!((segregation_index(&gaps) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn thirds_and_ends_skip_empty_slices() {
        let p = [f64::NAN, 0.9, 0.9, 0.1, 0.1, 0.1, 0.9, 0.9, 0.1, f64::NAN];
        // occupied: 0.9 0.9 0.1 | 0.1 0.1 0.9 | 0.9 0.1 -> n = 8, cuts at 3 and 5
        let t = thirds(&p);
        assert!((t[0] - (1.9 / 3.0)).abs() < 1e-12);
        assert!((t[1] - 0.1).abs() < 1e-12);
        assert!((t[2] - (1.9 / 3.0)).abs() < 1e-12, "{t:?}");
        let (lo, hi, mid) = ends_and_centre(&p, 2);
        assert!((lo - 0.9).abs() < 1e-12 && (hi - 0.5).abs() < 1e-12);
        assert!((mid - 0.3).abs() < 1e-12, "{mid}");
    }

    /// A field file of one window: 4 x-bins (-1.5..1.5), 4 y-bins (-1.5..1.5), 6 z-bins,
    /// the surface at y = 1 (top of bin 2) everywhere; in that bin w = `w(x, k)` and the big
    /// species (1) fills `share(k)` of the volume.
    fn field_file(
        dir: &std::path::Path,
        w: impl Fn(f64, usize) -> f64,
        share: impl Fn(usize) -> f64,
    ) -> std::path::PathBuf {
        use ndarray::{Array1, Array3, Array5};
        let path = dir.join("fields.h5");
        let f = hdf5::File::create(&path).unwrap();
        let g = f.create_group("fields").unwrap();
        let centres = |n: usize| Array1::from_iter((0..n).map(|i| i as f64 - 0.5 * (n - 1) as f64));
        let put1 = |name: &str, a: Array1<f64>| {
            g.new_dataset_builder().with_data(&a).create(name).unwrap();
        };
        put1("x", centres(4));
        put1("y", centres(4));
        put1("z", centres(6));
        put1("u0", Array1::from_elem(1, 0.5));
        let x = centres(4);
        let mut vel = Array5::<f64>::from_elem((1, 3, 4, 4, 6), f64::NAN);
        let mut vf = Array5::<f64>::zeros((1, 2, 4, 4, 6));
        for i in 0..4 {
            for k in 0..6 {
                vel[[0, 2, i, 2, k]] = w(x[i], k);
                vel[[0, 2, i, 1, k]] = 99.0; // below the surface: ignored
                vf[[0, 1, i, 2, k]] = 0.6 * share(k);
                vf[[0, 0, i, 2, k]] = 0.6 * (1.0 - share(k));
            }
        }
        g.new_dataset_builder()
            .with_data(&vel)
            .create("velocity")
            .unwrap();
        g.new_dataset_builder()
            .with_data(&vf)
            .create("volume_fraction")
            .unwrap();
        g.new_dataset_builder()
            .with_data(&Array3::<f64>::from_elem((1, 4, 6), 1.0))
            .create("surface")
            .unwrap();
        // the outermost x columns do not flow
        let mut boundary = Array3::<f64>::from_elem((1, 4, 6), -1.0);
        for k in 0..6 {
            boundary[[0, 0, k]] = f64::NAN;
            boundary[[0, 3, k]] = f64::NAN;
        }
        g.new_dataset_builder()
            .with_data(&boundary)
            .create("boundary")
            .unwrap();
        path
    }

    #[test]
    fn end_flow_reads_the_surface_bins_of_flowing_columns() {
        let dir = tempfile::tempdir().unwrap();
        // w = sign(x) (k + 1), and 50 in the non-flowing outer columns
        let path = field_file(
            dir.path(),
            |x, k| {
                if x.abs() > 1.0 {
                    50.0
                } else {
                    x.signum() * (k + 1) as f64
                }
            },
            |_| 0.5,
        );
        let r = RunReader::open(&path).unwrap();
        let f = end_flow(&r, 0, 2).unwrap();
        assert_eq!(f.low, [-1.5, 1.5]);
        assert_eq!(f.high, [-5.5, 5.5]);
        assert_eq!(f.centre, [-3.5, 3.5]);
        assert_eq!(f.u0, 0.5);
        assert!(end_flow(&r, 1, 2).is_err(), "there is one window only");
    }

    #[test]
    fn surface_share_is_the_big_species_share_of_the_top_bins() {
        let dir = tempfile::tempdir().unwrap();
        let path = field_file(
            dir.path(),
            |_, _| 0.0,
            |k| [0.2, 0.2, 0.9, 0.9, 0.2, 0.2][k],
        );
        let r = RunReader::open(&path).unwrap();
        let s = surface_share(&r, 0, 1).unwrap();
        for (got, want) in s.iter().zip([0.2, 0.2, 0.9, 0.9, 0.2, 0.2]) {
            assert!((got - want).abs() < 1e-12, "{s:?}");
        }
        let t = thirds(&s);
        assert!(t[1] > t[0].max(t[2]), "SLS: {t:?}");
    }

    #[test]
    fn late_profile_averages_the_last_samples() {
        let s = AxialSeries {
            rotations: vec![0.0, 1.0, 2.0, 3.0],
            big: vec![
                vec![0.0, 0.0],
                vec![0.2, f64::NAN],
                vec![0.4, f64::NAN],
                vec![0.6, 1.0],
            ],
            rule: BandRule {
                threshold: 0.2,
                min_slices: 1,
                periodic: false,
            },
        };
        let p = s.late_profile(2.0);
        assert!((p[0] - 0.5).abs() < 1e-12 && p[1] == 1.0);
        assert_eq!(s.late_profile(0.0), vec![0.6, 1.0]);
    }

    /// Two whole windows and a final fragment; in window 1 the big species' share and the
    /// angle rise together along 7 slices (one empty, one without an angle).
    #[test]
    fn angle_by_composition_reads_the_last_whole_window() {
        use ndarray::{Array1, Array2, Array3};
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("slices.h5");
        let f = hdf5::File::create(&path).unwrap();
        let g = f.create_group("slices").unwrap();
        let put1 = |name: &str, v: &[f64]| {
            let a = Array1::from_vec(v.to_vec());
            g.new_dataset_builder().with_data(&a).create(name).unwrap();
        };
        put1("rotations_start", &[0.0, 1.0, 2.0]);
        put1("rotations_end", &[1.0, 2.0, 2.02]);
        let share = [0.1, 0.2, f64::NAN, 0.5, 0.8, 0.9, 0.95];
        let angle = [20.0, 21.0, 22.0, f64::NAN, 28.0, 29.0, 30.0];
        let mut c = Array3::<f64>::from_elem((3, 2, 7), 0.5);
        let mut a = Array2::<f64>::from_elem((3, 7), 99.0); // the fragment: ignored
        for k in 0..7 {
            c[[1, 1, k]] = share[k];
            c[[1, 0, k]] = 1.0 - share[k];
            a[[1, k]] = angle[k];
        }
        g.new_dataset_builder()
            .with_data(&c)
            .create("concentration")
            .unwrap();
        g.new_dataset_builder()
            .with_data(&a)
            .create("angle")
            .unwrap();
        drop(g);
        drop(f);
        let r = RunReader::open(&path).unwrap();
        let m = angle_by_composition(&r, 1).unwrap();
        assert_eq!(m.window.index, 1);
        // usable slices: 0, 1, 4, 5, 6 -> thirds of 1: poorest slice 0, richest slice 6
        assert_eq!(m.poor, [0.1, 20.0]);
        assert_eq!(m.rich, [0.95, 30.0]);
        let m0 = angle_by_composition(&r, 0).unwrap();
        // species 0 reads the profile the other way round
        assert!(
            (m0.poor[0] - 0.05).abs() < 1e-12 && m0.poor[1] == 30.0,
            "{:?}",
            m0.poor
        );
        assert_eq!(m0.rich, [0.9, 20.0]);
    }
}
