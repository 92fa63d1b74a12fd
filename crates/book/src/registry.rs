//! The registry of book examples.

use crate::error::BookError;
use crate::output::ExampleOutput;

/// Everything an example may use when it runs.
#[derive(Debug, Clone, Default)]
pub struct RunContext {
    /// Whether to draw the figures and animations into [`ExampleOutput::figures`]; `false`
    /// computes the numbers only (and builds no figure).
    pub figures: bool,
    /// Contents of a measured-data CSV file (examples that take `--data`); `None` runs them on
    /// their shipped recording.
    pub data_csv: Option<String>,
}

/// One book example.
#[derive(Debug, Clone, Copy)]
pub struct Example {
    /// The book's MATLAB file stem, e.g. `p1c41_cdip_response`.
    pub id: &'static str,
    /// Short English title.
    pub title: &'static str,
    /// Part, chapter and section as the book numbers them, e.g. "Part 1 §4.1".
    pub section: &'static str,
    /// The parameter set used (e.g. "cart pendulum, table 3.5").
    pub parameters: &'static str,
    /// The measured data the example takes with `--data`: what, with the CSV columns (`None`:
    /// it takes none). An example whose recording ships in `data/rig/` runs on it when no file
    /// is given; one without shipped data returns [`BookError::NeedsData`] then.
    pub needs_data: Option<&'static str>,
    /// Runs the example.
    pub run: fn(&RunContext) -> Result<ExampleOutput, BookError>,
}

/// Every example, in book order.
pub fn registry() -> Vec<Example> {
    crate::chapters::all()
}

/// A file stem of the book's M-files that has no example of its own: a variant that only draws
/// (a `_plot` or `_custom` file), a helper function another M-file calls, or the M-file's own
/// spelling of an id. [`find`] runs the example it names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Alias {
    /// The M-file's stem, e.g. `p1c41_cdip_respose_custom`.
    pub stem: &'static str,
    /// The id of the example that computes what the M-file computes.
    pub id: &'static str,
    /// What the M-file is, and what of it (if anything) the example does not report.
    pub note: &'static str,
}

/// Every M-file stem of the book (folders `mfiles/p1c2` … `mfiles/p2c3` and
/// `mfiles/AutoGenU_InvPend` of its support material) that is not an example id, with the
/// example that covers it; the IP Toolbox samples are all example ids.
pub fn aliases() -> &'static [Alias] {
    ALIASES
}

const fn a(stem: &'static str, id: &'static str, note: &'static str) -> Alias {
    Alias { stem, id, note }
}

const ALIASES: &[Alias] = &[
    a(
        "cartident",
        "p1c221_id_cart",
        "the function p1c221_id_cart.m calls for each voltage step (K, T from the velocity)",
    ),
    a(
        "cdip_para2",
        "p1c221_id_cart",
        "the drive parameters ac = 6.250, bc = 4.362 that p1c221_id_cart.m prints",
    ),
    a(
        "p1c322_cdip_plot_MN",
        "p1c322_cdip_id_least_square",
        "draws the columns of M and N of the least-squares fit",
    ),
    a(
        "p1c332_adip_plot_pcont",
        "p1c332_adip_id_arm",
        "draws the five arm P-control records (k_P = 1 … 5); the example fits the k_P = 3 one",
    ),
    a(
        "p1c41_cdip_respose",
        "p1c41_cdip_response",
        "the M-file's own spelling of the example's stem",
    ),
    a(
        "p1c41_cdip_respose_custom",
        "p1c41_cdip_response",
        "the same responses with the book's figure styling",
    ),
    a(
        "p1c523_ex8_adip_lqr_plot",
        "p1c523_ex8_adip_lqr",
        "draws the nonlinear LQ simulation of example 5.8",
    ),
    a(
        "p1c74_ex1_cdip_Mc",
        "p1c74_ex1_cdip_ob_design",
        "the symbolic controllability matrix Mc, det(Mc) and rank(Mc) of the cart pendulum \
             (Symbolic Math Toolbox); the example reports the design, not Mc",
    ),
    a(
        "p1c74_ex1_cdip_ob_plot",
        "p1c74_ex1_cdip_ob_design",
        "draws and animates the output-feedback simulation of example 7.1",
    ),
    a(
        "mvert",
        "p2c13_ex5_adip_oc_robust_servo",
        "the vertex enumeration the polytopic p2c1 M-files call",
    ),
    a(
        "qf_polynomial",
        "p2c15_ex7_adip_oc_gs_servo",
        "the polynomial quadratic-form helper of the gain-scheduled design",
    ),
    a(
        "p2c234_ex1_cdip_odq_custom",
        "p2c234_ex1_cdip_odq",
        "the same runs with the book's figure styling",
    ),
    a(
        "p2c242_ex2_cart_ipd_custom",
        "p2c242_ex2_cart_ipd",
        "the same runs with the book's figure styling",
    ),
    a(
        "p2c244_ex3_cdip_sampled_data_lqr_sim_custom",
        "p2c244_ex3_cdip_sampled_data_lqr_sim",
        "the same runs with the book's figure styling",
    ),
    a(
        "p2c323_Sliding_Mode_Control",
        "p2c323_ex1_cdip_swing_up",
        "the sliding surface S of the swing-up's balancing phase",
    ),
    a(
        "p2c323_ex1_cdip_swing_up_custum",
        "p2c323_ex1_cdip_swing_up",
        "the same swing-up on the book's second Simulink model cdip_swing_up2_sim, whose \
             cart command passes a 0.5 quantizer and a ±0.5 saturation, with the book's figure \
             styling; the example runs the first model",
    ),
    a(
        "inputInvPendC",
        "p2c33_adip_nmpc_swing_up",
        "the problem (model, costs, bound, settings) AutoGenU turns into the C program",
    ),
    a(
        "plotsim",
        "p2c33_adip_nmpc_swing_up",
        "draws the C program's run",
    ),
    a(
        "animInvPend",
        "p2c33_adip_nmpc_swing_up",
        "animates the C program's run",
    ),
    a(
        "Format2",
        "p2c33_adip_nmpc_swing_up",
        "an AutoGenU code-generation package (Mathematica), computes nothing of the example",
    ),
    a(
        "Format3",
        "p2c33_adip_nmpc_swing_up",
        "an AutoGenU code-generation package (Mathematica), computes nothing of the example",
    ),
    a(
        "Optimize2",
        "p2c33_adip_nmpc_swing_up",
        "an AutoGenU code-generation package (Mathematica), computes nothing of the example",
    ),
];

/// The example with this id, or the example an M-file stem of [`aliases`] names.
///
/// # Errors
/// [`BookError::UnknownId`].
pub fn find(id: &str) -> Result<Example, BookError> {
    let target = aliases().iter().find(|a| a.stem == id).map_or(id, |a| a.id);
    registry()
        .into_iter()
        .find(|e| e.id == target)
        .ok_or_else(|| BookError::UnknownId(id.to_string()))
}
