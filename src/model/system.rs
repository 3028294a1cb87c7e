//! A forced, piecewise-smooth oscillator dx/dτ = f(τ, x) as the general engine sees it: a
//! state of up to [`MAX_DIM`] numbers, smooth pieces selected by a mode word, the switching
//! functions whose sign changes move between pieces, and the outputs the analyses read.

/// Most state variables a model may have.
pub const MAX_DIM: usize = 8;

/// A state, padded with zeros past the model's dimension.
pub type Vector = [f64; MAX_DIM];

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
    /// The mode at (τ, x): each kink on the branch its switching function's sign selects.
    fn mode_at(&mut self, tau: f64, x: &Vector) -> Mode;
    /// dx/dτ on the smooth piece `mode` (kinks held on their branches, so that an
    /// integrator keeps its order up to a located switch) into `dx`, and returns the mode
    /// the switching functions' signs select at (τ, x).
    fn field(&mut self, tau: f64, x: &Vector, mode: Mode, dx: &mut Vector) -> Mode;
    /// The switching functions' values on `mode` into `s` (for locating where one changes
    /// sign), and the mode their signs select.
    fn switching(&mut self, tau: f64, x: &Vector, mode: Mode, s: &mut [f64]) -> Mode;
    /// ∂f/∂x on the smooth piece `mode`: `jac[i][j]` = ∂f_i/∂x_j.
    fn jacobian(&mut self, tau: f64, x: &Vector, mode: Mode, jac: &mut [Vector; MAX_DIM]);
    /// The output whose max − min is the amplitude, and its rate of change.
    fn output(&mut self, tau: f64, x: &Vector, mode: Mode) -> (f64, f64);
    /// Whether (τ, x) has left the model (a collision ends the trajectory).
    fn collided(&mut self, tau: f64, x: &Vector) -> bool;
    /// Why (τ, x) gives a value that is not finite: the expression that first does, if the
    /// model can say.
    fn explain_non_finite(&mut self, tau: f64, x: &Vector) -> Option<String>;
}
