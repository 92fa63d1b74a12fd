//! Part 1 chapter 3: modelling and identification (book §3.1–3.4).
//!
//! The examples run on the rig measurements of `data/rig/` (embedded); the arm-rig examples
//! (`p1c332_*`) also take another recording with the same columns through `--data`. The
//! identification examples compute what the book's M-files of the same names compute (their
//! data windows, sample indices and formulas, cited by line), and report every number the
//! M-file displays under the M-file's variable names.

use super::common::*;
use super::mfile_refs::{OctaveDisplay, display_note, displayed_tf2};
use super::p1c2::{CartRun, simulate_cart};
use crate::error::BookError;
use crate::output::{ExampleOutput, Value};
use crate::registry::{Example, RunContext};
use pendulab_ident::{
    ArmPendulumConstants, CartPendulumConstants, Dataset, LsOptions, OscillationOptions,
    PeriodCorrection, arm_drive_ls, arm_pendulum_ls, cart_drive_ls, cart_pendulum_ls,
    free_oscillation, pendulum_from_oscillation, validate_arm_pendulum, validate_cart_pendulum,
    validate_drive, validate_oscillation, validate_p_step,
};
use pendulab_plants::{CartPendulum, CartPendulumParams, CartPendulumState};
use pendulab_plot::IdentFit;
use pendulab_sim::controllers::{OpenLoop, Pid, PidDiscretization, PidForm};
use pendulab_sim::rig::RigChains;
use pendulab_sim::{SampledLoop, SampledOptions, Signal};
use std::f64::consts::PI;

mod arm_rig;
mod cart_rig;
mod lagrange;
mod plot_pcont;
mod recipes;
use arm_rig::*;
use cart_rig::*;
use lagrange::*;
use plot_pcont::*;
use recipes::*;

const PCONT: [(f64, &str, &str); 4] = [
    (
        2.5,
        "cdip_cart_pcont_data_kP_025_ref_02.csv",
        include_str!("../../../../../data/rig/cdip_cart_pcont_data_kP_025_ref_02.csv"),
    ),
    (
        5.0,
        "cdip_cart_pcont_data_kP_050_ref_02.csv",
        include_str!("../../../../../data/rig/cdip_cart_pcont_data_kP_050_ref_02.csv"),
    ),
    (
        10.0,
        "cdip_cart_pcont_data_kP_100_ref_02.csv",
        include_str!("../../../../../data/rig/cdip_cart_pcont_data_kP_100_ref_02.csv"),
    ),
    (
        20.0,
        "cdip_cart_pcont_data_kP_200_ref_02.csv",
        include_str!("../../../../../data/rig/cdip_cart_pcont_data_kP_200_ref_02.csv"),
    ),
];
const PEND: &str = include_str!("../../../../../data/rig/cdip_pend_data.csv");
const LS: &str = include_str!("../../../../../data/rig/cdip_least_square_data.csv");
/// The arm rig's k_P = 3 P-control step (`p1c332_adip_id_arm.m`, line 10).
const ARM_STEP: (&str, &str) = (
    "adip_arm_pcont_data_kP_3_ref_1.csv",
    include_str!("../../../../../data/rig/adip_arm_pcont_data_kP_3_ref_1.csv"),
);
/// The arm rig's pendulum free oscillation (`p1c332_adip_id_pend.m`, line 4).
const ARM_PEND: (&str, &str) = (
    "adip_pend_data.csv",
    include_str!("../../../../../data/rig/adip_pend_data.csv"),
);
/// The arm rig's least-squares record (`p1c332_adip_id_least_square.m`, line 8).
const ARM_LS: (&str, &str) = (
    "adip_least_square_data.csv",
    include_str!("../../../../../data/rig/adip_least_square_data.csv"),
);

/// Time of the reference step in the rig's P-control recordings (s).
const STEP_TIME: f64 = 1.0;
/// Target of the rig's P-control recordings (m).
const TARGET: f64 = 0.2;

/// Columns and conventions of the arm-rig CSVs (`--data`; by default the shipped recordings).
const ARM_STEP_DATA: &str = "arm P-control step (k_P = 3, 1 rad reference step at t = 1 s; \
     default data/rig/adip_arm_pcont_data_kP_3_ref_1.csv): CSV columns t, theta1 (arm angle, \
     rad), theta2 optional (pendulum angle from hanging, rad)";
const ARM_PEND_DATA: &str = "arm pendulum free oscillation with the arm held, analysed over \
     50-66 s (default data/rig/adip_pend_data.csv): CSV columns t, theta2 (pendulum angle from \
     the hanging rest, rad)";
const ARM_LS_DATA: &str = "arm rig under any excitation, used over 1-9 s (default \
     data/rig/adip_least_square_data.csv): CSV columns t, phi1 (arm angle, rad), phi2 \
     (pendulum angle from hanging, rad), v (input voltage, V)";

fn ex(
    id: &'static str,
    title: &'static str,
    section: &'static str,
    parameters: &'static str,
    needs_data: Option<&'static str>,
    run: fn(&RunContext) -> Result<ExampleOutput, BookError>,
) -> Example {
    Example {
        id,
        title,
        section,
        parameters,
        needs_data,
        run,
    }
}

/// The chapter's examples, in book order.
pub(crate) fn examples() -> Vec<Example> {
    const CART: &str = "cart pendulum, table 3.5";
    const RIG: &str = "measured cart-rig data (data/rig/), table 3.5 constants m_p, l_p, g";
    const ARM: &str =
        "measured arm-rig data (data/rig/, or --data), table 3.7 constants L1, m2, l2, g";
    vec![
        ex(
            "p1c311_cdip_lagrange",
            "Equations of motion of the cart pendulum (Lagrange) and energy conservation",
            "Part 1 §3.1.1",
            CART,
            None,
            p1c311_cdip_lagrange,
        ),
        ex(
            "p1c321_cdip_plot_pcont",
            "Measured P-control steps of the cart rig (k_P = 2.5, 5, 10, 20)",
            "Part 1 §3.2.1",
            RIG,
            None,
            p1c321_cdip_plot_pcont,
        ),
        ex(
            "p1c321_cdip_id_cart",
            "Cart drive from the measured k_P = 10 step (peak time, overshoot)",
            "Part 1 §3.2.1",
            RIG,
            None,
            p1c321_cdip_id_cart,
        ),
        ex(
            "p1c321_cdip_id_pend",
            "Pendulum from the measured free oscillation (period, decay ratio)",
            "Part 1 §3.2.1",
            RIG,
            None,
            p1c321_cdip_id_pend,
        ),
        ex(
            "p1c322_cdip_id_least_square",
            "Least-squares identification of the cart rig (T_f = 0.075 s, 1–5 s)",
            "Part 1 §3.2.2",
            RIG,
            None,
            p1c322_cdip_id_least_square,
        ),
        ex(
            "p1c332_adip_id_arm",
            "Arm drive from a P-control step of the arm rig",
            "Part 1 §3.3",
            ARM,
            Some(ARM_STEP_DATA),
            p1c332_adip_id_arm,
        ),
        ex(
            "p1c332_adip_id_pend",
            "Arm-rig pendulum from its free oscillation",
            "Part 1 §3.3",
            ARM,
            Some(ARM_PEND_DATA),
            p1c332_adip_id_pend,
        ),
        ex(
            "p1c332_adip_id_least_square",
            "Least-squares identification of the arm rig",
            "Part 1 §3.3",
            ARM,
            Some(ARM_LS_DATA),
            p1c332_adip_id_least_square,
        ),
        ex(
            "p1c34_cdip_plot_pcont",
            "Nonlinear simulation of cart P control (k_P = 10, 0.2 m) against the rig",
            "Part 1 §3.4",
            CART,
            None,
            p1c34_cdip_plot_pcont,
        ),
    ]
}
