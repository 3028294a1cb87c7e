//! A forced, piecewise-smooth oscillator dx/dτ = f(τ, x) as the general engine sees it: a
//! state of up to [`MAX_DIM`] numbers, smooth pieces selected by a mode word, the switching
//! functions whose sign changes move between pieces, and the outputs the analyses read.

/// Most state variables a model may have.
pub const MAX_DIM: usize = 8;

/// A state, padded with zeros past the model's dimension.
pub type Vector = [f64; MAX_DIM];

/// The indices of a model's `dim` states other than the two its grid spans (`grid`), in the
/// model's order: the order after the grid's two in which tables and starts list them.
pub fn outside_grid(dim: usize, grid: [usize; 2]) -> impl Iterator<Item = usize> {
    (0..dim).filter(move |i| !grid.contains(i))
}

/// The smooth piece in force: bit k set where switching function k is on its first branch.
pub type Mode = u64;

/// A model the general engine integrates. Implementations hold their own scratch space
/// (hence `&mut self`); clone one per thread.
pub trait System: Clone + Send {
    /// Number of state variables.
    fn dim(&self) -> usize;
    /// The state variables' names.
    fn state_names(&self) -> &[String];
    /// The forcing period T = 2π/ω.
    fn period(&self) -> f64;
    /// Bits of the mode that can change along a trajectory.
    fn switch_mask(&self) -> Mode;
    /// Bits of the switching functions across which the field is continuous (the kinks of
    /// `max`, `min` and `abs`): a step taken a little past one of these errs by only the
    /// square of how far, where past any other it errs by as much.
    fn continuous_switches(&self) -> Mode;
    /// The mode at (τ, x): each kink on the branch its switching function's sign selects.
    fn mode_at(&mut self, tau: f64, x: &Vector) -> Mode;
    /// dx/dτ on the smooth piece `mode` (kinks held on their branches, so that an
    /// integrator keeps its order up to a located switch) into `dx`, and returns the mode
    /// the switching functions' signs select at (τ, x).
    fn field(&mut self, tau: f64, x: &Vector, mode: Mode, dx: &mut Vector) -> Mode;
    /// The switching functions' values on `mode` into `s` (for locating where one changes
    /// sign), and the mode their signs select.
    fn switching(&mut self, tau: f64, x: &Vector, mode: Mode, s: &mut [f64]) -> Mode;
    /// The output whose max − min is the amplitude, and its rate of change.
    fn output(&mut self, tau: f64, x: &Vector, mode: Mode) -> (f64, f64);
    /// Whether (τ, x) has left the model (a collision ends the trajectory), or a collision
    /// condition has no truth value there ([`System::undefined_collision`] says which).
    fn collided(&mut self, tau: f64, x: &Vector) -> bool;
    /// The collision condition that has no truth value at (τ, x) (a comparison of NaN), as
    /// `key = text`: the trajectory stops there with an error, not a collision.
    fn undefined_collision(&mut self, tau: f64, x: &Vector) -> Option<String>;
    /// Why (τ, x) gives a value that is not finite: the expression that first does, if the
    /// model can say.
    fn explain_non_finite(&mut self, tau: f64, x: &Vector) -> Option<String>;
    /// One plain RK4 step held on `mode` (the general engine's, the same bits) from `x` with
    /// first stage `k1`, by the model's own compiled code: its end into `end`, the
    /// derivative there into `dx`; returns the mode bits a stage or the end saw differ from
    /// `mode`, whether the end collided, and the switching functions at the end. `None`
    /// where the model has no such code (the engine takes the step stage by stage).
    fn compiled_step(
        &mut self,
        _step: &GridStep,
        _x: &Vector,
        _k1: &Vector,
        _mode: Mode,
        _end: &mut Vector,
        _dx: &mut Vector,
    ) -> Option<(Mode, bool, EndSwitching)> {
        None
    }
    /// Told the integrator's grid (`n` steps per period) as a trajectory starts: a model may
    /// tabulate what depends on time alone at the grid's stage times. Results must not
    /// depend on it beyond rounding.
    fn tabulate(&mut self, _n: usize) {}
}

/// A [`System`] whose field can be linearised: what the variational equations of
/// shooting and Floquet multipliers need besides the field (a model driven by a chirp has no
/// fixed period to shoot, and is not one).
pub trait Differentiable: System {
    /// dx/dτ into `dx` and ∂f/∂x into `jac` (`jac[i][j]` = ∂f_i/∂x_j), both on the smooth
    /// piece `mode`, in one evaluation (they share most of their work).
    fn field_and_jacobian(
        &mut self,
        tau: f64,
        x: &Vector,
        mode: Mode,
        dx: &mut Vector,
        jac: &mut [Vector; MAX_DIM],
    );
    /// The gradient of switching function `k` on `mode` into `grad` (∂h/∂x_j), and ∂h/∂τ.
    fn switch_gradient(
        &mut self,
        tau: f64,
        x: &Vector,
        mode: Mode,
        k: usize,
        grad: &mut Vector,
    ) -> f64;
}

/// How many switching values a compiled step gives at its end: the model's first.
pub const END_SWITCHES: usize = 8;

/// The switching functions at a compiled step's end, on the step's piece, as
/// [`System::switching`] gives them there (the same bits): the model's first
/// [`END_SWITCHES`] values (zero past its last switch) and the mode bits they show.
#[derive(Debug, Clone, Copy)]
pub struct EndSwitching {
    pub s: [f64; END_SWITCHES],
    pub seen: Mode,
}

/// A whole step of the integrator's grid: step `phase` of a forcing period of
/// `steps_per_period`, of length `h`, its middle and end at `t_half` and `t_end`.
#[derive(Debug, Clone, Copy)]
pub struct GridStep {
    pub phase: usize,
    pub steps_per_period: usize,
    pub h: f64,
    pub t_half: f64,
    pub t_end: f64,
}

/// A state of `len` ≤ [`MAX_DIM`] numbers, held inline (so it is `Copy`), read as a slice,
/// written and read back as a plain list of its numbers.
#[derive(Clone, Copy, PartialEq)]
pub struct StateVec {
    len: u8,
    x: Vector,
}

impl StateVec {
    /// The first `values.len()` (at most [`MAX_DIM`]) numbers of `values`.
    pub fn from_slice(values: &[f64]) -> StateVec {
        let len = values.len().min(MAX_DIM);
        let mut x = [0.0; MAX_DIM];
        x[..len].copy_from_slice(&values[..len]);
        StateVec { len: len as u8, x }
    }

    /// The first `dim` numbers of a padded state.
    pub fn of(x: &Vector, dim: usize) -> StateVec {
        StateVec::from_slice(&x[..dim.min(MAX_DIM)])
    }

    /// The state padded with zeros to [`MAX_DIM`].
    pub fn padded(&self) -> Vector {
        self.x
    }

    /// The first two numbers (the built-in model's whole state).
    pub fn pair(&self) -> [f64; 2] {
        [self.x[0], self.x[1]]
    }
}

impl From<[f64; 2]> for StateVec {
    fn from(x: [f64; 2]) -> StateVec {
        StateVec::from_slice(&x)
    }
}

impl std::ops::Deref for StateVec {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.x[..self.len as usize]
    }
}

impl std::ops::DerefMut for StateVec {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.x[..self.len as usize]
    }
}

impl std::fmt::Debug for StateVec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl serde::Serialize for StateVec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeSeq;
        let mut seq = s.serialize_seq(Some(self.len()))?;
        for v in self.iter() {
            seq.serialize_element(v)?;
        }
        seq.end()
    }
}

impl<'de> serde::Deserialize<'de> for StateVec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let values = Vec::<f64>::deserialize(d)?;
        if values.len() > MAX_DIM {
            return Err(serde::de::Error::custom(format!(
                "a state of {} numbers (at most {MAX_DIM})",
                values.len()
            )));
        }
        Ok(StateVec::from_slice(&values))
    }
}
