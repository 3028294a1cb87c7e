//! Floquet multipliers of a periodic response (eigenvalues of its n × n monodromy matrix),
//! its stability, and the test functions whose sign changes mark bifurcations. The 2 × 2 case
//! (the built-in model) has closed forms; larger ones go through the real Schur form.

use nalgebra::{DMatrix, Matrix2};
use serde::{Deserialize, Serialize};

/// A complex Floquet multiplier.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Multiplier {
    pub re: f64,
    pub im: f64,
}

impl Multiplier {
    pub fn modulus(&self) -> f64 {
        self.re.hypot(self.im)
    }
}

/// The multipliers (one per state variable), ordered by decreasing modulus.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Multipliers(pub Vec<Multiplier>);

/// The 2 × 2 matrix of a 2 × 2 `m`.
fn two_by_two(m: &DMatrix<f64>) -> Matrix2<f64> {
    Matrix2::new(m[(0, 0)], m[(0, 1)], m[(1, 0)], m[(1, 1)])
}

impl Multipliers {
    /// Eigenvalues of an n × n monodromy `m` (the closed form where n = 2).
    pub fn of_matrix(m: &DMatrix<f64>) -> Self {
        if m.nrows() == 2 {
            return Multipliers::of(&two_by_two(m));
        }
        let mut mu: Vec<Multiplier> = m
            .clone()
            .complex_eigenvalues()
            .iter()
            .map(|z| Multiplier { re: z.re, im: z.im })
            .collect();
        mu.sort_by(|a, b| b.modulus().total_cmp(&a.modulus()));
        Multipliers(mu)
    }

    /// Eigenvalues of `m` from its trace and determinant.
    pub fn of(m: &Matrix2<f64>) -> Self {
        let tr = m.trace();
        let det = m.determinant();
        let disc = 0.25 * tr * tr - det;
        let pair = if disc >= 0.0 {
            let r = disc.sqrt();
            // the larger root in the stable form, the smaller from the product
            let big = 0.5 * tr + r.copysign(tr);
            let small = if big != 0.0 { det / big } else { 0.5 * tr - r };
            vec![
                Multiplier { re: big, im: 0.0 },
                Multiplier { re: small, im: 0.0 },
            ]
        } else {
            let im = (-disc).sqrt();
            vec![
                Multiplier { re: 0.5 * tr, im },
                Multiplier {
                    re: 0.5 * tr,
                    im: -im,
                },
            ]
        };
        let mut pair = pair;
        if pair[1].modulus() > pair[0].modulus() {
            pair.swap(0, 1);
        }
        Multipliers(pair)
    }

    /// Largest modulus.
    pub fn spectral_radius(&self) -> f64 {
        self.0[0].modulus()
    }

    /// Every multiplier strictly inside the unit circle.
    pub fn stable(&self) -> bool {
        self.spectral_radius() < 1.0
    }

    /// The largest multiplier is one of a complex-conjugate pair.
    pub fn complex(&self) -> bool {
        self.0[0].im != 0.0
    }
}

/// The bifurcation test functions of a monodromy matrix M, each changing sign where a
/// multiplier crosses the unit circle in its own way.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TestFunctions {
    /// det(M − I) = (μ₁ − 1)(μ₂ − 1): a real multiplier through +1 (fold).
    pub fold: f64,
    /// det(M + I) = (μ₁ + 1)(μ₂ + 1): a real multiplier through −1 (period doubling).
    pub flip: f64,
    /// det M − 1 = μ₁μ₂ − 1 for a complex pair (Neimark–Sacker), else `None`; for n > 2,
    /// the product of |μ|² − 1 over the complex pairs.
    pub torus: Option<f64>,
}

impl TestFunctions {
    /// The test functions of an n × n monodromy `m` (the closed forms where n = 2).
    pub fn of_matrix(m: &DMatrix<f64>) -> Self {
        let n = m.nrows();
        if n == 2 {
            return TestFunctions::of(&two_by_two(m));
        }
        let identity = DMatrix::<f64>::identity(n, n);
        let mu = Multipliers::of_matrix(m);
        let pairs: Vec<f64> =
            mu.0.iter()
                .filter(|z| z.im > 0.0)
                .map(|z| z.re * z.re + z.im * z.im - 1.0)
                .collect();
        TestFunctions {
            fold: (m - &identity).determinant(),
            flip: (m + &identity).determinant(),
            torus: (!pairs.is_empty()).then(|| pairs.iter().product()),
        }
    }

    pub fn of(m: &Matrix2<f64>) -> Self {
        let tr = m.trace();
        let det = m.determinant();
        TestFunctions {
            fold: det - tr + 1.0,
            flip: det + tr + 1.0,
            torus: (tr * tr < 4.0 * det).then_some(det - 1.0),
        }
    }
}
