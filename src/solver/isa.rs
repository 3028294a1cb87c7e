//! The instruction sets the hot loops are compiled for, one chosen at run time.
//!
//! A release build runs on every x86-64 CPU: [`Rk4::advance_period`](super::Rk4) is compiled
//! three times (x86-64 baseline, x86-64-v3 with AVX2 and FMA, x86-64-v4 with AVX-512) and
//! the widest the CPU has is taken once per process. `mul_add` is a fused multiply-add in
//! every version (in hardware, or correctly rounded in software on a CPU without FMA), and
//! nothing else differs, so every version computes the same bits.
//!
//! Only what is inlined into a version takes its instructions. A closure is a function of
//! its own: one written in an `#[inline(always)]` body and not inlined (a large one, called
//! in several places) is compiled for the baseline, and each `mul_add` in it is a call. Hot
//! code reached from these versions is written as `#[inline(always)]` methods instead.
//!
//! `ISOLA_ISA` (`baseline`, `x86-64-v3` or `x86-64-v4`) chooses a narrower one, to compare
//! them; one the CPU lacks is refused at start.

use std::sync::OnceLock;

/// A set of instructions the hot loops are compiled for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Isa {
    /// Whatever the build targets (SSE2 on x86-64): runs everywhere.
    Baseline,
    /// x86-64-v3: AVX2, FMA, BMI1/2 (Haswell, Zen 1 and later).
    X86_64V3,
    /// x86-64-v4: v3 and AVX-512 F/BW/CD/DQ/VL (Skylake-X, Zen 4 and later).
    X86_64V4,
}

impl Isa {
    /// Every instruction set, narrowest first.
    pub const ALL: [Isa; 3] = [Isa::Baseline, Isa::X86_64V3, Isa::X86_64V4];

    /// The name `ISOLA_ISA` takes and the log shows.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Baseline => "baseline",
            Isa::X86_64V3 => "x86-64-v3",
            Isa::X86_64V4 => "x86-64-v4",
        }
    }

    /// True if this CPU can run code compiled for `self`.
    pub fn available(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            let v3 = || {
                is_x86_feature_detected!("avx2")
                    && is_x86_feature_detected!("fma")
                    && is_x86_feature_detected!("bmi1")
                    && is_x86_feature_detected!("bmi2")
                    && is_x86_feature_detected!("lzcnt")
                    && is_x86_feature_detected!("movbe")
                    && is_x86_feature_detected!("f16c")
            };
            let v4 = || {
                is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512bw")
                    && is_x86_feature_detected!("avx512cd")
                    && is_x86_feature_detected!("avx512dq")
                    && is_x86_feature_detected!("avx512vl")
            };
            match self {
                Isa::Baseline => true,
                Isa::X86_64V3 => v3(),
                Isa::X86_64V4 => v3() && v4(),
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self == Isa::Baseline
        }
    }

    /// The widest instruction set this CPU has.
    pub fn widest() -> Isa {
        *Isa::ALL
            .iter()
            .rev()
            .find(|isa| isa.available())
            .unwrap_or(&Isa::Baseline)
    }
}

/// Why `ISOLA_ISA` cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum IsaError {
    #[error("ISOLA_ISA = {0:?} is not an instruction set: baseline, x86-64-v3 or x86-64-v4")]
    Unknown(String),
    #[error("ISOLA_ISA = {0}: this CPU lacks it (it has {1})")]
    Unavailable(&'static str, &'static str),
}

/// The instruction set named by `ISOLA_ISA`, or the widest this CPU has if it is unset.
pub fn from_env() -> Result<Isa, IsaError> {
    let Some(wanted) = std::env::var_os("ISOLA_ISA") else {
        return Ok(Isa::widest());
    };
    let wanted = wanted.to_string_lossy();
    let isa = Isa::ALL
        .into_iter()
        .find(|isa| isa.name() == wanted.trim())
        .ok_or_else(|| IsaError::Unknown(wanted.to_string()))?;
    if isa.available() {
        Ok(isa)
    } else {
        Err(IsaError::Unavailable(isa.name(), Isa::widest().name()))
    }
}

static CHOSEN: OnceLock<Isa> = OnceLock::new();

/// Fixes the instruction set of this process from `ISOLA_ISA` (see [`from_env`]); the binary
/// calls it at start, so that a bad `ISOLA_ISA` is an error there.
pub fn choose() -> Result<Isa, IsaError> {
    let isa = from_env()?;
    Ok(*CHOSEN.get_or_init(|| isa))
}

/// The instruction set of this process: the one [`choose`] fixed, or else [`from_env`]'s,
/// falling back to the widest when `ISOLA_ISA` is unusable.
#[inline]
pub fn chosen() -> Isa {
    *CHOSEN.get_or_init(|| from_env().unwrap_or_else(|_| Isa::widest()))
}
