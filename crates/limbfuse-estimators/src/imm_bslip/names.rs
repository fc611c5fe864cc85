//! Diagnostic columns of [`super::ImmBslip`]. They depend on the library:
//! one weight per (gait, phase) model, `w_gNN_PHASE` for gait `NN` (by
//! increasing speed; the estimate header maps `gNN` to its speed) and phase
//! `ss1`, `ds`, `ss2`, then [`SPEED_MEAN`].

/// Largest number of gaits (3 weights each must fit [`limbfuse_core::MAX_DIAG`]).
pub const MAX_GAITS: usize = 20;

/// Weight names, index `3 * gait + phase`.
pub const WEIGHT_NAMES: [&str; 3 * MAX_GAITS] = [
    "w_g00_ss1",
    "w_g00_ds",
    "w_g00_ss2",
    "w_g01_ss1",
    "w_g01_ds",
    "w_g01_ss2",
    "w_g02_ss1",
    "w_g02_ds",
    "w_g02_ss2",
    "w_g03_ss1",
    "w_g03_ds",
    "w_g03_ss2",
    "w_g04_ss1",
    "w_g04_ds",
    "w_g04_ss2",
    "w_g05_ss1",
    "w_g05_ds",
    "w_g05_ss2",
    "w_g06_ss1",
    "w_g06_ds",
    "w_g06_ss2",
    "w_g07_ss1",
    "w_g07_ds",
    "w_g07_ss2",
    "w_g08_ss1",
    "w_g08_ds",
    "w_g08_ss2",
    "w_g09_ss1",
    "w_g09_ds",
    "w_g09_ss2",
    "w_g10_ss1",
    "w_g10_ds",
    "w_g10_ss2",
    "w_g11_ss1",
    "w_g11_ds",
    "w_g11_ss2",
    "w_g12_ss1",
    "w_g12_ds",
    "w_g12_ss2",
    "w_g13_ss1",
    "w_g13_ds",
    "w_g13_ss2",
    "w_g14_ss1",
    "w_g14_ds",
    "w_g14_ss2",
    "w_g15_ss1",
    "w_g15_ds",
    "w_g15_ss2",
    "w_g16_ss1",
    "w_g16_ds",
    "w_g16_ss2",
    "w_g17_ss1",
    "w_g17_ds",
    "w_g17_ss2",
    "w_g18_ss1",
    "w_g18_ds",
    "w_g18_ss2",
    "w_g19_ss1",
    "w_g19_ds",
    "w_g19_ss2",
];

/// Name of the column after the weights: the weight-averaged library speed.
pub const SPEED_MEAN: &str = "speed_mean";

/// One diagnostic of [`super::ImmBslip`]; its column is
/// [`super::ImmBslip::diagnostic_column`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImmDiag {
    /// Weight (mode probability, paper 003 eq 8) of model `k`, in the order
    /// of [`super::ImmBslip::weights`].
    Weight(usize),
    /// `sum_j w_j v_j` over the gaits: the weight-averaged library speed (m/s).
    SpeedMean,
}
