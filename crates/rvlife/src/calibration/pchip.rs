//! Monotone cubic interpolation of the reference studies' stage values.

/// Monotone piecewise-cubic Hermite interpolation (Fritsch and Carlson, SIAM J. Numer. Anal.
/// 17, 1980; end slopes as in Moler, Numerical Computing with MATLAB, `pchip`), linear beyond
/// the ends. Keeps a monotone series monotone and is continuously differentiable.
#[derive(Debug, Clone)]
pub(super) struct Pchip {
    x: Vec<f64>,
    y: Vec<f64>,
    d: Vec<f64>,
}

impl Pchip {
    /// `x` strictly increasing, at least 2 points.
    pub(super) fn new(x: Vec<f64>, y: Vec<f64>) -> Pchip {
        let n = x.len();
        let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let del: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
        let mut d = vec![0.0; n];
        if n == 2 {
            d = vec![del[0]; 2];
        } else {
            for i in 1..n - 1 {
                if del[i - 1] * del[i] > 0.0 {
                    let w1 = 2.0 * h[i] + h[i - 1];
                    let w2 = h[i] + 2.0 * h[i - 1];
                    d[i] = (w1 + w2) / (w1 / del[i - 1] + w2 / del[i]);
                }
            }
            let end = |h0: f64, h1: f64, d0: f64, d1: f64| {
                let s = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
                if s * d0 <= 0.0 {
                    0.0
                } else if d0 * d1 < 0.0 && s.abs() > 3.0 * d0.abs() {
                    3.0 * d0
                } else {
                    s
                }
            };
            d[0] = end(h[0], h[1], del[0], del[1]);
            d[n - 1] = end(h[n - 2], h[n - 3], del[n - 2], del[n - 3]);
        }
        Pchip { x, y, d }
    }

    /// Value and derivative at `t`.
    pub(super) fn eval(&self, t: f64) -> (f64, f64) {
        let n = self.x.len();
        if t <= self.x[0] {
            return (self.y[0] + self.d[0] * (t - self.x[0]), self.d[0]);
        }
        if t >= self.x[n - 1] {
            return (
                self.y[n - 1] + self.d[n - 1] * (t - self.x[n - 1]),
                self.d[n - 1],
            );
        }
        let i = self.x.partition_point(|&v| v <= t).clamp(1, n - 1) - 1;
        let h = self.x[i + 1] - self.x[i];
        let s = (t - self.x[i]) / h;
        let (y0, y1, d0, d1) = (self.y[i], self.y[i + 1], self.d[i], self.d[i + 1]);
        let v = (2.0 * s.powi(3) - 3.0 * s * s + 1.0) * y0
            + (s.powi(3) - 2.0 * s * s + s) * h * d0
            + (-2.0 * s.powi(3) + 3.0 * s * s) * y1
            + (s.powi(3) - s * s) * h * d1;
        let dv = (6.0 * s * s - 6.0 * s) / h * y0
            + (3.0 * s * s - 4.0 * s + 1.0) * d0
            + (-6.0 * s * s + 6.0 * s) / h * y1
            + (3.0 * s * s - 2.0 * s) * d1;
        (v, dv)
    }
}
