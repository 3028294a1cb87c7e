//! Parsers for the range and grid flags: `0.2:6.0:0.05`, `201x251`, `-0.8:0.8`.

use isola::analysis::grid::Axis;
use isola::analysis::resolution::{Integrators, ResolutionSetting};

/// `--resolution`: `128` (RK4 steps per forcing period) or `rtol=1e-12` (Dormand–Prince).
pub fn resolution(s: &str) -> Result<ResolutionSetting, String> {
    ResolutionSetting::parse(s)
}

/// Sets `--resolution`, if given, on `spec`; an error names the flag where the command's
/// integrator takes the other form.
pub fn set_resolution(
    spec: &mut impl Integrators,
    resolution: Option<ResolutionSetting>,
) -> anyhow::Result<()> {
    if let Some(setting) = resolution {
        spec.set_resolution(setting)
            .map_err(|e| anyhow::anyhow!("--resolution {e}"))?;
    }
    Ok(())
}

/// A finite number (`1e400`, `nan` and `inf` are refused as written).
pub fn finite(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(format!("'{s}' is not a finite number")),
        Err(_) => Err(format!("'{s}' is not a number")),
    }
}

/// `START:END:STEP` (inclusive, STEP > 0, either direction) or a single value.
pub fn range(s: &str) -> Result<Axis, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let num = finite;
    match parts.as_slice() {
        [v] => {
            let v = num(v)?;
            Ok(Axis::new(v, v, 1))
        }
        [a, b, step] => {
            let (a, b, step) = (num(a)?, num(b)?, num(step)?);
            if !(step > 0.0 && step.is_finite()) {
                return Err(format!("step {step} must be > 0"));
            }
            let n = ((b - a).abs() / step + 1e-9).floor() as usize + 1;
            if n > 100_000 {
                return Err(format!("{n} values: at most 100000"));
            }
            let end = a + (n - 1) as f64 * step * (b - a).signum();
            Ok(Axis::new(a, end, n))
        }
        _ => Err(format!("'{s}': expected START:END:STEP or a single value")),
    }
}

/// `MIN:MAX`, both finite, MIN < MAX.
pub fn interval(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = interval_any(s)?;
    if a > b {
        return Err(format!("'{s}': MIN must be below MAX"));
    }
    Ok((a, b))
}

/// `START:END` in either direction, both finite and different.
pub fn interval_any(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s
        .split_once(':')
        .ok_or_else(|| format!("'{s}': expected START:END"))?;
    let number = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("'{t}' is not a finite number"))
    };
    let (a, b) = (number(a)?, number(b)?);
    if a == b {
        return Err(format!("'{s}': START and END must differ"));
    }
    Ok((a, b))
}

/// `NXxNV`, e.g. `201x251`.
pub fn grid(s: &str) -> Result<(usize, usize), String> {
    let (a, b) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}': expected NxM, e.g. 201x251"))?;
    let a: usize = a
        .trim()
        .parse()
        .map_err(|_| format!("'{a}' is not a count"))?;
    let b: usize = b
        .trim()
        .parse()
        .map_err(|_| format!("'{b}' is not a count"))?;
    if a == 0 || b == 0 || a > 16384 || b > 16384 {
        return Err(format!("'{s}': each side between 1 and 16384"));
    }
    Ok((a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_grids_and_intervals() {
        let r = range("0.2:6.0:0.05").unwrap();
        assert_eq!(r.points, 117);
        assert!((r.max - 6.0).abs() < 1e-9);
        let r = range("6:0:0.5").unwrap();
        assert_eq!((r.points, r.min, r.max), (13, 6.0, 0.0));
        assert_eq!(range("3.7").unwrap().points, 1);
        assert!(
            range("0:1:0").is_err() && range("a:1:0.1").is_err() && range("0:1e9:1e-9").is_err()
        );
        assert_eq!(grid("201x251").unwrap(), (201, 251));
        assert!(grid("0x3").is_err() && grid("201").is_err());
        assert_eq!(interval("-0.8:0.8").unwrap(), (-0.8, 0.8));
        assert!(interval("1:0").is_err());
    }
}
