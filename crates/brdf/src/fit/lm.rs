//! Levenberg–Marquardt for small nonlinear least-squares problems: minimise ½ Σ r_k(x)².
//!
//! Each step solves the damped normal equations (JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr (Marquardt's
//! scaling, which makes the step invariant to the units of each parameter) by Cholesky in f64.
//! A step that lowers the cost is taken and λ shrinks; one that does not is refused and λ
//! grows, moving the step towards scaled gradient descent. The Jacobian is by central
//! differences, so the residual function only has to be evaluable.
//! Sources: K. Levenberg, Q. Appl. Math. 2(2), 1944; D. W. Marquardt, J. SIAM 11(2), 1963;
//! K. Madsen, H. B. Nielsen, O. Tingleff, "Methods for Non-Linear Least Squares Problems",
//! DTU lecture notes, 2004, §3.2 (the damping update).

/// Stopping rules and the finite-difference step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LmOptions {
    /// Most iterations (accepted or refused steps).
    pub max_iterations: usize,
    /// Stop when an accepted step lowers the cost by less than this fraction.
    pub cost_tolerance: f64,
    /// Stop when every |δ_j| ≤ step_tolerance · (|x_j| + step_tolerance).
    pub step_tolerance: f64,
    /// Central-difference step for the Jacobian, per unit of max(1, |x_j|).
    pub fd_step: f64,
}

impl Default for LmOptions {
    fn default() -> Self {
        LmOptions { max_iterations: 200, cost_tolerance: 1e-12, step_tolerance: 1e-10, fd_step: 1e-6 }
    }
}

/// What a run ended with.
#[derive(Clone, Debug, PartialEq)]
pub struct LmResult {
    /// The parameters found.
    pub x: Vec<f64>,
    /// ½ Σ r² at `x`.
    pub cost: f64,
    /// Iterations used.
    pub iterations: usize,
    /// True when a tolerance was met (false: out of iterations or the damping ran away).
    pub converged: bool,
}

/// ½ Σ r².
fn half_sq(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|v| v * v).sum::<f64>()
}

/// The Jacobian ∂r_k/∂x_j by central differences, column by column (`jac[j][k]`).
pub fn jacobian(f: &mut dyn FnMut(&[f64], &mut [f64]), x: &[f64], m: usize, fd_step: f64) -> Vec<Vec<f64>> {
    let mut cols = Vec::with_capacity(x.len());
    let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
    let mut xp = x.to_vec();
    for j in 0..x.len() {
        let h = fd_step * x[j].abs().max(1.0);
        xp[j] = x[j] + h;
        f(&xp, &mut rp);
        xp[j] = x[j] - h;
        f(&xp, &mut rm);
        xp[j] = x[j];
        cols.push(rp.iter().zip(&rm).map(|(a, b)| (a - b) / (2.0 * h)).collect());
    }
    cols
}

/// Solves A x = b for symmetric positive definite A (n × n, row-major) by Cholesky;
/// `None` when A is not numerically positive definite.
pub fn cholesky_solve(a: &[f64], b: &[f64]) -> Option<Vec<f64>> {
    let n = b.len();
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let s = a[i * n + j] - (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum::<f64>();
            if i == j {
                if !(s > 0.0 && s.is_finite()) {
                    return None;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        y[i] = (b[i] - (0..i).map(|k| l[i * n + k] * y[k]).sum::<f64>()) / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = (y[i] - (i + 1..n).map(|k| l[k * n + i] * x[k]).sum::<f64>()) / l[i * n + i];
    }
    Some(x)
}

/// Minimises ½ Σ r_k(x)² from `x0`; `f(x, r)` writes the `m` residuals at `x` into `r`.
/// A non-finite residual counts as an infinite cost, so the search backs away from it.
pub fn minimize(mut f: impl FnMut(&[f64], &mut [f64]), x0: &[f64], m: usize, opts: &LmOptions) -> LmResult {
    let n = x0.len();
    let mut x = x0.to_vec();
    let mut r = vec![0.0; m];
    f(&x, &mut r);
    let mut cost = half_sq(&r);
    let finite = |c: f64| if c.is_finite() { c } else { f64::INFINITY };
    cost = finite(cost);
    let mut lambda = 1e-3;
    let mut trial = vec![0.0; m];
    let mut iterations = 0;
    let mut converged = false;
    'outer: while iterations < opts.max_iterations {
        let jac = jacobian(&mut f, &x, m, opts.fd_step);
        let mut jtj = vec![0.0; n * n];
        let mut jtr = vec![0.0; n];
        for a in 0..n {
            jtr[a] = jac[a].iter().zip(&r).map(|(j, r)| j * r).sum();
            for b in 0..=a {
                let v: f64 = jac[a].iter().zip(&jac[b]).map(|(p, q)| p * q).sum();
                jtj[a * n + b] = v;
                jtj[b * n + a] = v;
            }
        }
        if jtr.iter().all(|g| *g == 0.0) {
            converged = true;
            break;
        }
        // Try damped steps until one lowers the cost.
        loop {
            iterations += 1;
            let mut damped = jtj.clone();
            for a in 0..n {
                // A zero diagonal (a parameter with no effect) still gets some damping.
                damped[a * n + a] += lambda * jtj[a * n + a].max(1e-12 * (1.0 + jtj[a * n + a]));
            }
            let rhs: Vec<f64> = jtr.iter().map(|g| -g).collect();
            let step = cholesky_solve(&damped, &rhs);
            if let Some(delta) = step {
                let xt: Vec<f64> = x.iter().zip(&delta).map(|(a, d)| a + d).collect();
                f(&xt, &mut trial);
                let ct = finite(half_sq(&trial));
                if ct < cost {
                    let small_step = delta
                        .iter()
                        .zip(&x)
                        .all(|(d, v)| d.abs() <= opts.step_tolerance * (v.abs() + opts.step_tolerance));
                    let small_gain = cost - ct <= opts.cost_tolerance * cost;
                    x = xt;
                    std::mem::swap(&mut r, &mut trial);
                    cost = ct;
                    lambda = (lambda / 3.0).max(1e-12);
                    if small_step || small_gain {
                        converged = true;
                        break 'outer;
                    }
                    continue 'outer;
                }
                let tiny =
                    delta.iter().zip(&x).all(|(d, v)| d.abs() <= opts.step_tolerance * (v.abs() + opts.step_tolerance));
                if tiny {
                    // No representable step lowers the cost: a minimum to working precision.
                    converged = true;
                    break 'outer;
                }
            }
            lambda *= 4.0;
            if lambda > 1e16 || iterations >= opts.max_iterations {
                break 'outer;
            }
        }
    }
    LmResult { x, cost, iterations, converged }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rosenbrock_minimum_is_found() {
        // Rosenbrock as least squares: r = (10(x₂ − x₁²), 1 − x₁), minimum 0 at (1, 1);
        // the classic start (−1.2, 1) must follow the curved valley.
        let res = minimize(
            |x, r| {
                r[0] = 10.0 * (x[1] - x[0] * x[0]);
                r[1] = 1.0 - x[0];
            },
            &[-1.2, 1.0],
            2,
            &LmOptions::default(),
        );
        assert!(res.converged, "{res:?}");
        assert!((res.x[0] - 1.0).abs() < 1e-6 && (res.x[1] - 1.0).abs() < 1e-6, "{res:?}");
        assert!(res.cost < 1e-12, "{res:?}");
    }

    #[test]
    fn exponential_decay_is_recovered() {
        // y = a e^(−b t) + c sampled exactly; from a start far off, LM returns (a, b, c).
        let (a, b, c) = (2.5, 0.7, 0.3);
        let t: Vec<f64> = (0..40).map(|k| k as f64 * 0.25).collect();
        let y: Vec<f64> = t.iter().map(|t| a * (-b * t).exp() + c).collect();
        let res = minimize(
            |x, r| {
                for k in 0..t.len() {
                    r[k] = x[0] * (-x[1] * t[k]).exp() + x[2] - y[k];
                }
            },
            &[1.0, 2.0, 0.0],
            t.len(),
            &LmOptions::default(),
        );
        assert!(res.converged, "{res:?}");
        for (got, want) in res.x.iter().zip([a, b, c]) {
            assert!((got - want).abs() < 1e-6, "{res:?}");
        }
    }

    #[test]
    fn cholesky_solves_and_refuses_indefinite() {
        let a = [4.0, 2.0, 2.0, 3.0];
        let x = cholesky_solve(&a, &[2.0, 1.0]).unwrap();
        assert!((4.0 * x[0] + 2.0 * x[1] - 2.0).abs() < 1e-12 && (2.0 * x[0] + 3.0 * x[1] - 1.0).abs() < 1e-12);
        assert!(cholesky_solve(&[1.0, 2.0, 2.0, 1.0], &[1.0, 1.0]).is_none());
    }
}
