//! The response type ω_r : ω_e from the strongest harmonic of a period-k orbit.

use std::f64::consts::PI;
use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// ω_r : ω_e as a reduced fraction: 2:1 super-harmonic, 1:1 harmonic, 1:2 and 1:3
/// subharmonic...
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Ratio {
    pub response: u32,
    pub excitation: u32,
}

impl fmt::Display for Ratio {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.response, self.excitation)
    }
}

impl Serialize for Ratio {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl std::str::FromStr for Ratio {
    type Err = String;

    /// `m:k`, as [`Ratio`] displays it.
    fn from_str(text: &str) -> Result<Self, String> {
        let parsed = text
            .split_once(':')
            .and_then(|(m, k)| Some((m.parse::<u32>().ok()?, k.parse::<u32>().ok()?)));
        match parsed {
            Some((m, k)) if k > 0 => Ok(Ratio::new(m, k)),
            _ => Err(format!("'{text}' is not a ratio m:k")),
        }
    }
}

impl<'de> Deserialize<'de> for Ratio {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        String::deserialize(d)?
            .parse()
            .map_err(serde::de::Error::custom)
    }
}

impl Ratio {
    /// m:k reduced.
    pub fn new(m: u32, k: u32) -> Self {
        let g = gcd(m, k).max(1);
        Ratio {
            response: m / g,
            excitation: k / g,
        }
    }

    /// The ratio of a period-`k` orbit sampled uniformly over k forcing periods: its
    /// strongest harmonic m·ω_e/k, m = 1 … 4k (DC excluded), gives m:k.
    pub fn of_samples(samples: &[f64], k: usize) -> Self {
        let n = samples.len();
        let mean = samples.iter().sum::<f64>() / n as f64;
        let max_m = (4 * k).min(n / 2 - 1).max(1);
        let power = |m: usize| {
            let w = 2.0 * PI * m as f64 / n as f64;
            let (mut re, mut im) = (0.0, 0.0);
            for (j, &x) in samples.iter().enumerate() {
                let (s, c) = (w * j as f64).sin_cos();
                re += (x - mean) * c;
                im += (x - mean) * s;
            }
            re * re + im * im
        };
        let m = (1..=max_m)
            .map(|m| (m, power(m)))
            .fold((1, f64::NEG_INFINITY), |best, (m, p)| {
                if p > best.1 * (1.0 + 1e-9) {
                    (m, p)
                } else {
                    best
                }
            })
            .0;
        Ratio::new(m as u32, k as u32)
    }
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a } else { gcd(b, a % b) }
}
