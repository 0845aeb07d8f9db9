//! Conjugate gradients for a surface spanned over held nodes: the free entries of `u` that make
//! `A u` vanish on the free rows, the held entries kept as they are. Used where a net or a plate
//! is hung between nodes that something else places: the drape predictor
//! ([`crate::core::solver`]) and the wrinkle measure's reference surfaces
//! ([`crate::core::wrinkles::amplitude`]).

/// Improves `u` in place by conjugate gradients on the symmetric positive semi-definite
/// operator `apply` (`apply(v, out)` sets `out = A v`, zero on the held rows, whatever `v`
/// holds at the held entries: they enter the free rows as they are). Stops when the residual
/// `‖A u‖` on the free rows is at most `relative` times its start or `absolute` (N, mm: the
/// caller's units), when it is zero, or after `max_iterations`.
pub fn relax_free(
    mut apply: impl FnMut(&[f64], &mut [f64]),
    u: &mut [f64],
    relative: f64,
    absolute: f64,
    max_iterations: usize,
) {
    let n = u.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
    let mut r = vec![0.0; n];
    apply(u, &mut r);
    r.iter_mut().for_each(|v| *v = -*v);
    // The search direction is zero on the held rows, so `apply` sees the free part alone.
    let mut p = r.clone();
    let mut rr = dot(&r, &r);
    let stop = (relative * rr.sqrt()).max(absolute);
    let mut ap = vec![0.0; n];
    for _ in 0..max_iterations {
        if rr.sqrt() <= stop || rr == 0.0 {
            break;
        }
        apply(&p, &mut ap);
        let pap = dot(&p, &ap);
        if pap <= 0.0 {
            break;
        }
        let alpha = rr / pap;
        for i in 0..n {
            u[i] += alpha * p[i];
            r[i] -= alpha * ap[i];
        }
        let next = dot(&r, &r);
        let beta = next / rr;
        rr = next;
        for i in 0..n {
            p[i] = r[i] + beta * p[i];
        }
    }
}
