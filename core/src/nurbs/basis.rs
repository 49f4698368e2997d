//! B-spline basis functions (The NURBS Book, §2.5: A2.1 span search, A2.2
//! non-vanishing basis functions, A2.3 basis derivatives) and knot-vector
//! helpers. These are the building blocks every curve and surface here
//! uses; the styling module reuses them for uniform cubic B-splines.

/// The span index `i` with `knots[i] <= u < knots[i+1]` for the curve with
/// `n_ctrl` control points and degree `p` (A2.1). `u` is clamped into the
/// domain `[knots[p], knots[n_ctrl]]`; at the domain end the last
/// non-empty span is returned.
pub fn find_span(n_ctrl: usize, p: usize, u: f64, knots: &[f64]) -> usize {
    let n = n_ctrl - 1;
    if u >= knots[n + 1] {
        // Last non-empty span.
        let mut i = n;
        while i > p && knots[i] >= knots[n + 1] {
            i -= 1;
        }
        return i;
    }
    if u <= knots[p] {
        let mut i = p;
        while i < n && knots[i + 1] <= knots[p] {
            i += 1;
        }
        return i;
    }
    let (mut lo, mut hi) = (p, n + 1);
    let mut mid = (lo + hi) / 2;
    while u < knots[mid] || u >= knots[mid + 1] {
        if u < knots[mid] {
            hi = mid;
        } else {
            lo = mid;
        }
        mid = (lo + hi) / 2;
    }
    mid
}

/// The `p + 1` non-vanishing basis functions `N_{span-p..=span, p}(u)` (A2.2).
pub fn basis_funs(span: usize, u: f64, p: usize, knots: &[f64]) -> Vec<f64> {
    let mut n = vec![0.0; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    n[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let denom = right[r + 1] + left[j - r];
            let temp = if denom == 0.0 { 0.0 } else { n[r] / denom };
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    n
}

/// Basis functions and their derivatives up to order `d` (A2.3):
/// `ders[k][j]` is the k-th derivative of `N_{span-p+j, p}` at `u`.
pub fn ders_basis_funs(span: usize, u: f64, p: usize, d: usize, knots: &[f64]) -> Vec<Vec<f64>> {
    let mut ndu = vec![vec![0.0; p + 1]; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = if ndu[j][r] == 0.0 {
                0.0
            } else {
                ndu[r][j - 1] / ndu[j][r]
            };
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = vec![vec![0.0; p + 1]; d + 1];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let mut a = vec![vec![0.0; p + 1]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=d.min(p) {
            let mut dd = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let den = ndu[pk + 1][rk as usize];
                a[s2][0] = if den == 0.0 { 0.0 } else { a[s1][0] / den };
                dd = a[s2][0] * ndu[rk as usize][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if (r as isize - 1) <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                let den = ndu[pk + 1][idx];
                a[s2][j] = if den == 0.0 {
                    0.0
                } else {
                    (a[s1][j] - a[s1][j - 1]) / den
                };
                dd += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                let den = ndu[pk + 1][r];
                a[s2][k] = if den == 0.0 { 0.0 } else { -a[s1][k - 1] / den };
                dd += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = dd;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut fac = p as f64;
    for k in 1..=d.min(p) {
        for j in 0..=p {
            ders[k][j] *= fac;
        }
        fac *= (p - k) as f64;
    }
    ders
}

/// A clamped uniform knot vector on `[0, 1]` for `n_ctrl` control points of
/// degree `p`: `p + 1` zeros, equally spaced interior knots, `p + 1` ones.
pub fn clamped_uniform_knots(n_ctrl: usize, p: usize) -> Vec<f64> {
    let m = n_ctrl + p + 1;
    let spans = n_ctrl - p;
    (0..m)
        .map(|i| {
            if i <= p {
                0.0
            } else if i >= n_ctrl {
                1.0
            } else {
                (i - p) as f64 / spans as f64
            }
        })
        .collect()
}

/// A uniform (unclamped, periodic) knot vector with knots `(i - p) / spans`
/// for `n_ctrl` control points of degree `p`; the domain is `[0, 1]`.
pub fn periodic_uniform_knots(n_ctrl: usize, p: usize) -> Vec<f64> {
    let spans = (n_ctrl - p) as f64;
    (0..n_ctrl + p + 1)
        .map(|i| (i as f64 - p as f64) / spans)
        .collect()
}

/// Knots averaged from parameters (The NURBS Book eq. 9.8), clamped.
pub fn averaged_knots(params: &[f64], p: usize) -> Vec<f64> {
    let n = params.len() - 1;
    let mut knots = vec![params[0]; p + 1];
    for j in 1..=(n - p) {
        let s: f64 = params[j..j + p].iter().sum();
        knots.push(s / p as f64);
    }
    knots.extend(std::iter::repeat_n(params[n], p + 1));
    knots
}

/// Distinct knot values with their multiplicities, in order.
pub fn knot_multiplicities(knots: &[f64]) -> Vec<(f64, usize)> {
    let mut out: Vec<(f64, usize)> = Vec::new();
    for &k in knots {
        match out.last_mut() {
            Some((v, m)) if *v == k => *m += 1,
            _ => out.push((k, 1)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_of_unity_and_derivative_sum() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.5, 0.9, 1.0, 1.0, 1.0, 1.0];
        let p = 3;
        let n_ctrl = knots.len() - p - 1;
        for i in 0..=50 {
            let u = i as f64 / 50.0;
            let span = find_span(n_ctrl, p, u, &knots);
            let b = basis_funs(span, u, p, &knots);
            assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            let d = ders_basis_funs(span, u, p, 2, &knots);
            for (j, bj) in b.iter().enumerate() {
                assert!((d[0][j] - bj).abs() < 1e-14);
            }
            assert!(d[1].iter().sum::<f64>().abs() < 1e-10);
            assert!(d[2].iter().sum::<f64>().abs() < 1e-8);
        }
    }

    #[test]
    fn derivative_matches_finite_difference() {
        let knots = [0.0, 0.0, 0.0, 0.3, 0.6, 1.0, 1.0, 1.0];
        let p = 2;
        let n_ctrl = 5;
        let u = 0.45;
        let h = 1e-6;
        let span = find_span(n_ctrl, p, u, &knots);
        let d = ders_basis_funs(span, u, p, 1, &knots);
        let bp = basis_funs(span, u + h, p, &knots);
        let bm = basis_funs(span, u - h, p, &knots);
        for j in 0..=p {
            assert!(((bp[j] - bm[j]) / (2.0 * h) - d[1][j]).abs() < 1e-6);
        }
    }
}
