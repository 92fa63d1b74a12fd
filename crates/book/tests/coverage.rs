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

/// Every M-file of the book's support material (folders `mfiles/<chapter>/` and
/// `ip_toolbox/sample_*/`), as `folder/stem`, written out from the folders' listing.
const BOOK_MFILES: &[&str] = &[
    "AutoGenU_InvPend/Format2",
    "AutoGenU_InvPend/Format3",
    "AutoGenU_InvPend/Optimize2",
    "AutoGenU_InvPend/animInvPend",
    "AutoGenU_InvPend/inputInvPendC",
    "AutoGenU_InvPend/plotsim",
    "p1c2/cartident",
    "p1c2/cdip_para2",
    "p1c2/p1c211_pcont",
    "p1c2/p1c212_pdcont",
    "p1c2/p1c213_picont",
    "p1c2/p1c213_pidbode",
    "p1c2/p1c213_pidcont",
    "p1c2/p1c221_id_cart",
    "p1c2/p1c223_pcont",
    "p1c2/p1c224_i_pdcont",
    "p1c2/p1c224_p_dcont",
    "p1c2/p1c23_crane",
    "p1c3/p1c311_cdip_lagrange",
    "p1c3/p1c321_cdip_id_cart",
    "p1c3/p1c321_cdip_id_pend",
    "p1c3/p1c321_cdip_plot_pcont",
    "p1c3/p1c322_cdip_id_least_square",
    "p1c3/p1c322_cdip_plot_MN",
    "p1c3/p1c332_adip_id_arm",
    "p1c3/p1c332_adip_id_least_square",
    "p1c3/p1c332_adip_id_pend",
    "p1c3/p1c332_adip_plot_pcont",
    "p1c3/p1c34_cdip_plot_pcont",
    "p1c4/p1c41_cdip_respose",
    "p1c4/p1c41_cdip_respose_custom",
    "p1c4/p1c43_lyapunov_func",
    "p1c4/p1c43_stability1",
    "p1c4/p1c43_stability2",
    "p1c5/p1c511_ex1",
    "p1c5/p1c511_ex2",
    "p1c5/p1c511_ex3_adip",
    "p1c5/p1c511_ex4_cdip",
    "p1c5/p1c512_ex5",
    "p1c5/p1c522_ex6",
    "p1c5/p1c522_ex7_adip_place",
    "p1c5/p1c523_ex8_adip_lqr",
    "p1c5/p1c523_ex8_adip_lqr_plot",
    "p1c6/p1c62_ex1_cart_p_step",
    "p1c6/p1c62_ex2_cart_pi_ramp",
    "p1c6/p1c62_ex3_cart_p_step_dis",
    "p1c6/p1c62_ex4_cart_pi_step_dis",
    "p1c6/p1c63_ex5_cdip_lqr_servo",
    "p1c7/p1c74_ex1_cdip_Mc",
    "p1c7/p1c74_ex1_cdip_ob_design",
    "p1c7/p1c74_ex1_cdip_ob_plot",
    "p1c7/p1c74_ex2_cdip_Mo",
    "p1c7/p1c75_ex3_cdip_detectability",
    "p1c8/p1c83_ex1_zero_order_hold",
    "p1c8/p1c83_ex2_cdip_ob_design_zoh",
    "p1c8/p1c84_ex3_bilinear",
    "p1c8/p1c84_ex4_cdip_ob_design_bilinear",
    "p2c1/mvert",
    "p2c1/p2c112_ex1_alpha_stability",
    "p2c1/p2c121_ex3_alpha_stability_opt",
    "p2c1/p2c122_ex4_adip_oc_multiobjective_servo",
    "p2c1/p2c122_ex4_adip_oc_servo",
    "p2c1/p2c13_ex5_adip_lqr_servo",
    "p2c1/p2c13_ex5_adip_oc_nominal_servo",
    "p2c1/p2c13_ex5_adip_oc_robust_servo",
    "p2c1/p2c14_ex6_adip_oc_saturation",
    "p2c1/p2c15_ex7_adip_lqr_servo",
    "p2c1/p2c15_ex7_adip_oc_gs_servo",
    "p2c1/qf_polynomial",
    "p2c2/p2c234_ex1_cdip_odq",
    "p2c2/p2c234_ex1_cdip_odq_custom",
    "p2c2/p2c242_ex2_cart_ipd",
    "p2c2/p2c242_ex2_cart_ipd_custom",
    "p2c2/p2c244_ex3_cdip_sampled_data_lqr_sim",
    "p2c2/p2c244_ex3_cdip_sampled_data_lqr_sim_custom",
    "p2c3/p2c323_Sliding_Mode_Control",
    "p2c3/p2c323_ex1_cdip_swing_up",
    "p2c3/p2c323_ex1_cdip_swing_up_custum",
    "sample_adip/adip_lqr_servo_sim",
    "sample_adip/adip_lqr_sim",
    "sample_adip/adip_pdcont_sim",
    "sample_cdip/cdip_lqr_servo_sim",
    "sample_cdip/cdip_lqr_sim",
    "sample_cdip/cdip_pdcont_sim",
];

#[test]
fn every_mfile_has_an_example_or_an_alias() {
    let ids: Vec<&str> = pendulab_book::registry().iter().map(|e| e.id).collect();
    let aliases = pendulab_book::registry::aliases();
    for path in BOOK_MFILES {
        let stem = path.rsplit('/').next().unwrap();
        let as_id = ids.contains(&stem);
        let alias = aliases.iter().find(|a| a.stem == stem);
        assert!(
            as_id != alias.is_some(),
            "{path}: an example id ({as_id}) or an alias ({alias:?}), exactly one"
        );
        let e = pendulab_book::find(stem).unwrap_or_else(|e| panic!("{path}: {e}"));
        assert_eq!(e.id, alias.map_or(stem, |a| a.id), "{path}");
    }
    // Every alias is an M-file's stem, and every example is an M-file's stem or the one example
    // without an M-file of its own (the C program of Part 2 §3.3).
    for a in aliases {
        assert!(
            BOOK_MFILES
                .iter()
                .any(|p| p.ends_with(&format!("/{}", a.stem))),
            "alias {} is no M-file",
            a.stem
        );
        assert!(!a.note.trim().is_empty(), "alias {}: empty note", a.stem);
    }
    for id in ids {
        assert!(
            id == "p2c33_adip_nmpc_swing_up"
                || id == "p1c41_cdip_response"
                || BOOK_MFILES.iter().any(|p| p.ends_with(&format!("/{id}"))),
            "example {id} is no M-file's stem"
        );
    }
}

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
