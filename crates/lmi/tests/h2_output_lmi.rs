//! Output-feedback H2 synthesis by LMIs (`synthesis::h2_output_feedback_lmi`, the change of
//! variables of Scherer, Gahinet & Chilali) cross-checked against the Riccati synthesis of
//! `pendulab-lti` (`design::h2_syn`: two independent algorithms) on the fixture plants of
//! `tools/reference/hinf_reference.py` with `D₁₁ = 0`, and the defining property: the
//! closed loop of the reconstructed controller is stable with `h2_norm` equal to the
//! certified `√min tr W`.

use pendulab_lmi::synthesis::{HinfLmiOptions, h2_output_feedback_lmi};
use pendulab_lmi::{Backend, SolveOptions};

use pendulab_lti::design::h2_syn;
use pendulab_lti::norms::h2_norm;

#[path = "../../lti/tests/hinf_support/mod.rs"]
mod hinf_support;
use hinf_support::cases;

fn options(backend: Backend) -> HinfLmiOptions {
    HinfLmiOptions {
        solve: SolveOptions {
            backend,
            ..SolveOptions::default()
        },
        ..HinfLmiOptions::default()
    }
}

/// Relative agreement of `√min tr W` with the Riccati optimum: the solves run in balanced
/// coordinates (`synthesis::hinf` module docs), which bring the mixed-sensitivity plant
/// (`A` entries from 10⁻³ to 80, an unbounded `Y` at the optimum) to the accuracy of the
/// others (seen: 3e-8 dense, 3e-6 Clarabel).
const AGREEMENT: f64 = 1e-5;

/// Every fixture plant with `D₁₁ = 0` on both solvers: `√min tr W` equals the Riccati
/// optimum, and the reconstructed controller's closed loop is stable with `h2_norm` between
/// the optimum and the certified value; plants with `D₁₁ ≠ 0` are refused.
#[test]
fn h2_output_feedback_matches_riccati() {
    for backend in [Backend::Clarabel, Backend::Dense] {
        let mut checked = 0;
        for (name, plant, _) in cases() {
            if plant.d11().iter().any(|v| *v != 0.0) {
                assert!(h2_output_feedback_lmi(&plant, &options(backend)).is_err());
                continue;
            }
            let riccati = h2_syn(&plant).unwrap();
            let lmi = h2_output_feedback_lmi(&plant, &options(backend)).unwrap();
            let norm = lmi
                .norm
                .unwrap_or_else(|| panic!("{name} {backend:?}: {:?}", lmi.status));
            assert!(
                (norm - riccati.norm).abs() <= AGREEMENT * riccati.norm,
                "{name} {backend:?}: {norm} vs {}",
                riccati.norm
            );
            let design = lmi.design.unwrap();
            assert!(
                design.closed_loop.is_stable().unwrap(),
                "{name} {backend:?}"
            );
            let actual = h2_norm(&design.closed_loop).unwrap();
            assert!(
                actual <= norm * (1.0 + 1e-6) && actual >= riccati.norm * (1.0 - 1e-9),
                "{name} {backend:?}: closed loop {actual}, certified {norm}, optimum {}",
                riccati.norm
            );
            checked += 1;
        }
        assert_eq!(checked, 5);
    }
}
