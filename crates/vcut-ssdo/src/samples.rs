//! Sample sets: M sets of N points in the unit half-ball (z ≥ 0), from the Halton sequence in
//! bases 2, 3, 5 (the authors' demo), one set per pixel by a 4 × 4 interleaved pattern.
//! A point p gives the direction p/|p| (uniform over the hemisphere, since the points are
//! uniform in the half-ball) and the distance |p|·r_max.

use glam::Vec3;

/// The radical inverse of `i` in `base`.
fn radical_inverse(mut i: u64, base: u64) -> f64 {
    let (mut inv, mut f) = (0.0, 1.0 / base as f64);
    while i > 0 {
        inv += (i % base) as f64 * f;
        i /= base;
        f /= base as f64;
    }
    inv
}

/// M interleaved sets of N half-ball points.
#[derive(Debug, Clone)]
pub struct SampleSets {
    /// Points per set.
    pub n: usize,
    /// The sets, each `n` points; set `k` is used by pixels with `(x mod 4) + 4 (y mod 4) = k mod M`.
    pub sets: Vec<Vec<Vec3>>,
}

impl SampleSets {
    /// `m` sets of `n` Halton points in the unit half-ball (rejection from the box
    /// [−1, 1]² × [0, 1]; points within 5 % of the centre are skipped so no sample sits on the
    /// surface itself).
    pub fn halton(n: usize, m: usize) -> SampleSets {
        let (n, m) = (n.max(1), m.max(1));
        let mut points = Vec::with_capacity(n * m);
        let mut i = 1u64;
        while points.len() < n * m {
            let p = Vec3::new(
                (radical_inverse(i, 2) * 2.0 - 1.0) as f32,
                (radical_inverse(i, 3) * 2.0 - 1.0) as f32,
                radical_inverse(i, 5) as f32,
            );
            i += 1;
            let r = p.length();
            if (0.05..=1.0).contains(&r) {
                points.push(p);
            }
        }
        SampleSets { n, sets: points.chunks(n).map(<[Vec3]>::to_vec).collect() }
    }

    /// The set pixel `(x, y)` uses.
    #[inline]
    pub fn for_pixel(&self, x: usize, y: usize) -> &[Vec3] {
        &self.sets[((x % 4) + 4 * (y % 4)) % self.sets.len()]
    }
}

/// An orthonormal basis `(t, b)` completing unit `n` (Duff et al. 2017).
#[inline]
pub fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_sets_fill_the_half_ball_evenly() {
        let s = SampleSets::halton(16, 16);
        assert_eq!(s.sets.len(), 16);
        let all: Vec<Vec3> = s.sets.iter().flatten().copied().collect();
        assert!(all.iter().all(|p| p.z >= 0.0 && p.length() <= 1.0));
        // Uniform directions over the hemisphere: mean cos θ = 1/2, mean direction along +z.
        let mean_cos = all.iter().map(|p| p.normalize().z).sum::<f32>() / all.len() as f32;
        assert!((mean_cos - 0.5).abs() < 0.03, "{mean_cos}");
        let mean_xy = all.iter().map(|p| p.normalize()).sum::<Vec3>() / all.len() as f32;
        assert!(mean_xy.x.abs() < 0.03 && mean_xy.y.abs() < 0.03);
        // Uniform in volume: mean radius 3/4 (of the shell from 0.05).
        let mean_r = all.iter().map(|p| p.length()).sum::<f32>() / all.len() as f32;
        assert!((mean_r - 0.75).abs() < 0.03, "{mean_r}");
        assert_ne!(s.for_pixel(0, 0), s.for_pixel(1, 0));
        assert_eq!(s.for_pixel(0, 0), s.for_pixel(4, 4));
    }

    #[test]
    fn the_basis_is_orthonormal() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()] {
            let (t, b) = basis(n);
            assert!(t.dot(n).abs() < 1e-5 && b.dot(n).abs() < 1e-5 && t.dot(b).abs() < 1e-5);
            assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
        }
    }
}
