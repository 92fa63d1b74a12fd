//! The registry holds every example of the book, once, under the book's file stem.
//!
//! The id list below is the checklist of the book's examples, written out by hand from the
//! book's M-files (one stem per example, part 1 ch. 2 to part 2 ch. 3, then the IP Toolbox
//! samples) in the book's order; it is the independent source this test checks the registry
//! against.

const BOOK_EXAMPLE_IDS: &[&str] = &[
    "p1c211_pcont",
    "p1c212_pdcont",
    "p1c213_picont",
    "p1c213_pidcont",
    "p1c213_pidbode",
    "p1c221_id_cart",
    "p1c223_pcont",
    "p1c224_p_dcont",
    "p1c224_i_pdcont",
    "p1c23_crane",
    "p1c311_cdip_lagrange",
    "p1c321_cdip_plot_pcont",
    "p1c321_cdip_id_cart",
    "p1c321_cdip_id_pend",
    "p1c322_cdip_id_least_square",
    "p1c332_adip_id_arm",
    "p1c332_adip_id_pend",
    "p1c332_adip_id_least_square",
    "p1c34_cdip_plot_pcont",
    "p1c41_cdip_response",
    "p1c43_stability1",
    "p1c43_stability2",
    "p1c43_lyapunov_func",
    "p1c511_ex1",
    "p1c511_ex2",
    "p1c511_ex3_adip",
    "p1c511_ex4_cdip",
    "p1c512_ex5",
    "p1c522_ex6",
    "p1c522_ex7_adip_place",
    "p1c523_ex8_adip_lqr",
    "p1c62_ex1_cart_p_step",
    "p1c62_ex2_cart_pi_ramp",
    "p1c62_ex3_cart_p_step_dis",
    "p1c62_ex4_cart_pi_step_dis",
    "p1c63_ex5_cdip_lqr_servo",
    "p1c74_ex1_cdip_ob_design",
    "p1c74_ex2_cdip_Mo",
    "p1c75_ex3_cdip_detectability",
    "p1c83_ex1_zero_order_hold",
    "p1c83_ex2_cdip_ob_design_zoh",
    "p1c84_ex3_bilinear",
    "p1c84_ex4_cdip_ob_design_bilinear",
    "p2c112_ex1_alpha_stability",
    "p2c121_ex3_alpha_stability_opt",
    "p2c122_ex4_adip_oc_servo",
    "p2c122_ex4_adip_oc_multiobjective_servo",
    "p2c13_ex5_adip_lqr_servo",
    "p2c13_ex5_adip_oc_nominal_servo",
    "p2c13_ex5_adip_oc_robust_servo",
    "p2c14_ex6_adip_oc_saturation",
    "p2c15_ex7_adip_lqr_servo",
    "p2c15_ex7_adip_oc_gs_servo",
    "p2c234_ex1_cdip_odq",
    "p2c242_ex2_cart_ipd",
    "p2c244_ex3_cdip_sampled_data_lqr_sim",
    "p2c323_ex1_cdip_swing_up",
    "p2c33_adip_nmpc_swing_up",
    "cdip_pdcont_sim",
    "cdip_lqr_sim",
    "cdip_lqr_servo_sim",
    "adip_pdcont_sim",
    "adip_lqr_sim",
    "adip_lqr_servo_sim",
];

#[test]
fn registry_lists_every_book_example_once() {
    let ids: Vec<&str> = pendulab_book::registry().iter().map(|e| e.id).collect();
    for id in BOOK_EXAMPLE_IDS {
        let n = ids.iter().filter(|x| *x == id).count();
        assert_eq!(n, 1, "{id} appears {n} times in the registry");
    }
    for id in &ids {
        assert!(
            BOOK_EXAMPLE_IDS.contains(id),
            "{id} is in the registry but not in the book's list of examples"
        );
    }
}

#[test]
fn every_example_states_its_section_parameters_and_title() {
    for e in pendulab_book::registry() {
        assert!(!e.title.trim().is_empty(), "{}: empty title", e.id);
        assert!(!e.section.trim().is_empty(), "{}: empty section", e.id);
        assert!(
            !e.parameters.trim().is_empty(),
            "{}: empty parameters",
            e.id
        );
    }
}

#[test]
fn unknown_id_is_a_typed_error() {
    match pendulab_book::find("p9c99_no_such_example") {
        Err(pendulab_book::BookError::UnknownId(id)) => assert_eq!(id, "p9c99_no_such_example"),
        other => panic!("expected UnknownId, got {other:?}"),
    }
}
