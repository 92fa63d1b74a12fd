//! Part 1 ch. 5 examples: controllability, canonical form, pole placement, LQR.
//!
//! Independent references: the book's printed values (part 1 ch. 5), closed forms worked out in the
//! comments, and SciPy 1.17.1 / SymPy 1.14.0 values printed by
//! `tools/reference/book_p1c5_reference.py`.

mod common;
use common::*;

use pendulab_book::Value;

#[test]
fn p1c511_ex1() {
    let out = run("p1c511_ex1");
    // M_c = [B, AB] with AB = [1; 2] (integer arithmetic, exact).
    assert_eq!(
        out.get("Mc"),
        Some(&Value::Matrix(vec![vec![1.0, 1.0], vec![1.0, 2.0]]))
    );
    assert_eq!(num(&out, "rank"), 2.0);
    all_reproduced(&out);
}

#[test]
fn p1c511_ex2() {
    let out = run("p1c511_ex2");
    // M_c = [B, AB, A²B] = [[0,0,0],[0,1,0],[1,0,0]]: rank 2 (book example 5.2).
    assert_eq!(num(&out, "rank"), 2.0);
    all_reproduced(&out);
}

#[test]
fn p1c511_ex3_adip() {
    let out = run("p1c511_ex3_adip");
    // SymPy on the same data (tools/reference/book_p1c5_reference.py): det M_c(0) =
    // −88052627.0230987, det M_c(π/2) = 1234.18543709219. The 4×4 determinant of entries up
    // to ~1e4 is accurate to ~1e-16·1e8 absolute: 1e-9 relative at 0, 1e-6 relative for the
    // small value at π/2 (cancellation of the large terms).
    let d0 = num(&out, "det_Mc_at_0");
    assert!(
        (d0 - (-88052627.0230987)).abs() <= 1e-9 * 88052627.0,
        "{d0}"
    );
    let d90 = num(&out, "det_Mc_at_pi_over_2");
    assert!((d90 - 1234.18543709219).abs() <= 1e-6 * 1234.2, "{d90}");
    // Without friction it vanishes (exactly in exact arithmetic; cos(π/2) ≈ 6e-17 here).
    let d90_free = num(&out, "det_Mc_at_pi_over_2_mu2_zero");
    assert!(d90_free.abs() <= 1e-12 * d0.abs(), "{d90_free}");
}

#[test]
fn p1c511_ex4_cdip() {
    let out = run("p1c511_ex4_cdip");
    // Different pendulums: controllable (book example 5.4), full rank 6. Identical pendulums:
    // θa − θb and its rate obey an input-free equation, so exactly 2 directions are lost.
    assert_eq!(num(&out, "rank_different"), 6.0);
    assert_eq!(num(&out, "rank_identical"), 4.0);
    all_reproduced(&out);
}

#[test]
fn p1c512_ex5() {
    let out = run("p1c512_ex5");
    // Book example 5.5: T = [[−1, 1], [0, 1]], Â = [[0, 1], [−1, 2]] (integers; 1e-12 for rounding
    // in the eigen-solver's characteristic polynomial of the double root 1).
    let Some(Value::Matrix(t)) = out.get("T") else {
        panic!()
    };
    let Some(Value::Matrix(a)) = out.get("A_hat") else {
        panic!()
    };
    assert_rel(&t.concat(), &[-1.0, 1.0, 0.0, 1.0], 1e-12, "T");
    assert_rel(&a.concat(), &[0.0, 1.0, -1.0, 2.0], 1e-12, "A_hat");
    all_reproduced(&out);
}

#[test]
fn p1c522_ex6() {
    let out = run("p1c522_ex6");
    // Closed form: A + BK = [[1 + k1, k2], [1 + k1, 1 + k2]] has trace 2 + k1 + k2 and
    // determinant 1 + k1; (s + 1)(s + 2) needs trace −3, det 2: K = [1, −6] (u = +Kx).
    assert_rel(&vector(&out, "K"), &[1.0, -6.0], 1e-12, "K");
    all_reproduced(&out);
}

#[test]
fn p1c522_ex7_adip_place() {
    let out = run("p1c522_ex7_adip_place");
    // SciPy place_poles (single input: the gain is unique), book convention. Relative 1e-8:
    // the companion-form conditioning of this 4-state system costs a few digits.
    assert_rel(
        &vector(&out, "K"),
        &[
            0.0824421307669,
            8.33432204754,
            0.522267633711,
            1.25049281876,
        ],
        1e-8,
        "K",
    );
    all_reproduced(&out);
}

#[test]
fn p1c523_ex8_adip_lqr() {
    let out = run("p1c523_ex8_adip_lqr");
    // SciPy solve_continuous_are (cross-checked with python-control lqr), book convention.
    // Relative 1e-8: Riccati residuals are ~1e-12 on these systems.
    let want = [
        (
            "K_case1",
            [3.16227766017, 42.7134127869, 2.68530164921, 6.77220439257],
        ),
        (
            "K_case2",
            [1.0, 22.9453582197, 1.34005350349, 3.61837459785],
        ),
        (
            "K_case3",
            [4.472135955, 48.0564903614, 3.17261756052, 7.60619478015],
        ),
    ];
    for ((name, k), (q1, r)) in want
        .iter()
        .zip([(10.0f64, 1.0f64), (10.0, 10.0), (20.0, 1.0)])
    {
        let got = vector(&out, name);
        assert_rel(&got, k, 1e-8, name);
        // Closed form: θ1 enters A only through its integrator, so the Kalman identity at
        // s → 0 gives |K_θ1| = √(q1/R).
        assert!((got[0] - (q1 / r).sqrt()).abs() < 1e-9, "{name}");
    }
    // The arm reaches the 45° equilibrium in 3 s (the slowest closed-loop pole of case 2,
    // about −1.1, has decayed by e^{-3} ≈ 5 % of 45°, so within 3°).
    for case in ["case1", "case2", "case3"] {
        let f = num(&out, &format!("theta1_final_deg_{case}"));
        assert!((f - 45.0).abs() < 3.0, "{case}: {f}");
    }
}

#[test]
fn figures_are_written() {
    let dir = TempDir::new("p1c5");
    for id in [
        "p1c511_ex3_adip",
        "p1c522_ex7_adip_place",
        "p1c523_ex8_adip_lqr",
    ] {
        let (_, files) = dir.run(id, None);
        assert!(!files.is_empty(), "{id}");
        assert_figures_larger(&files, 2000);
        if id == "p1c523_ex8_adip_lqr" {
            // Time responses (SVG + PNG) and the animation (GIF + SMIL SVG).
            for ext in ["svg", "png", "gif"] {
                assert!(
                    files
                        .iter()
                        .any(|f| f.extension().is_some_and(|e| e == ext)),
                    "{ext}"
                );
            }
        }
    }
}
