//! Velocity Verlet for translation and rotation (thesis eq. 2.19): a half kick, a drift, the
//! force evaluation with the predicted (half-step) velocities, and a second half kick.

/// `v += h F/m` and `w += h T/I` for the first `n` particles, with `h = dt/2`.
#[allow(clippy::too_many_arguments)]
pub fn half_kick(
    n: usize,
    h: f64,
    v: &mut [[f64; 3]],
    w: &mut [[f64; 3]],
    f: &[[f64; 3]],
    t: &[[f64; 3]],
    inv_mass: &[f64],
    inv_inertia: &[f64],
) {
    for i in 0..n {
        let a = h * inv_mass[i];
        let b = h * inv_inertia[i];
        for k in 0..3 {
            v[i][k] += a * f[i][k];
            w[i][k] += b * t[i][k];
        }
    }
}

/// `x += dt v` for the first `n` particles; with `period = Some(L)` the axial coordinate is
/// wrapped into `[-L/2, L/2)`.
pub fn drift(n: usize, dt: f64, x: &mut [[f64; 3]], v: &[[f64; 3]], period: Option<f64>) {
    for i in 0..n {
        for k in 0..3 {
            x[i][k] += dt * v[i][k];
        }
        if let Some(l) = period {
            x[i][2] = wrap(x[i][2], l);
        }
    }
}

/// Wrap `z` into `[-L/2, L/2)` (one period at most, as a particle moves far less per step).
#[inline]
pub fn wrap(z: f64, l: f64) -> f64 {
    let half = 0.5 * l;
    if z >= half {
        z - l
    } else if z < -half {
        z + l
    } else {
        z
    }
}

/// Minimum image of an axial separation `dz` in a periodic drum of length `l`.
#[inline]
pub fn min_image(dz: f64, l: f64) -> f64 {
    let half = 0.5 * l;
    if dz > half {
        dz - l
    } else if dz < -half {
        dz + l
    } else {
        dz
    }
}
