//! The hot paths do not allocate: a counting global allocator around C/GMRES updates and
//! the controllers' `update` (the `Controller` contract: no allocation inside `update`).

use pendulab_control::cgmres::{
    Cgmres, CgmresOptions, InitOptions, InputBound, InputBounds, NmpcController,
    OptimalControlProblem,
};
use pendulab_sim::Controller;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        COUNT.with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        COUNT.with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations<F: FnOnce()>(f: F) -> usize {
    let before = COUNT.with(|c| c.get());
    f();
    COUNT.with(|c| c.get()) - before
}

/// A cart-like nonlinear test problem (4 states, 1 input).
struct Cartish;

impl OptimalControlProblem for Cartish {
    fn nx(&self) -> usize {
        4
    }
    fn nu(&self) -> usize {
        1
    }
    fn state_equation(&self, _t: f64, x: &[f64], u: &[f64], dx: &mut [f64]) {
        dx[0] = x[2];
        dx[1] = x[3];
        dx[2] = -6.0 * x[2] + 4.0 * u[0];
        dx[3] = 30.0 * x[1].sin() - x[1].cos() * dx[2];
    }
    fn hamiltonian_x(&self, _t: f64, x: &[f64], u: &[f64], l: &[f64], hx: &mut [f64]) {
        let a = -6.0 * x[2] + 4.0 * u[0];
        hx[0] = x[0];
        hx[1] = x[1] + l[3] * (30.0 * x[1].cos() + x[1].sin() * a);
        hx[2] = l[0] - 6.0 * l[2] + 6.0 * x[1].cos() * l[3];
        hx[3] = l[1];
    }
    fn hamiltonian_u(&self, _t: f64, x: &[f64], u: &[f64], l: &[f64], hu: &mut [f64]) {
        hu[0] = 0.1 * u[0] + 4.0 * l[2] - 4.0 * x[1].cos() * l[3];
    }
    fn terminal_gradient(&self, _t: f64, x: &[f64], phix: &mut [f64]) {
        phix.copy_from_slice(x);
    }
}

#[test]
fn cgmres_update_and_nmpc_controller_do_not_allocate() {
    let p = InputBounds::new(Cartish, vec![InputBound::symmetric(0, 2.0, 0.01)]).unwrap();
    let guess = p.stage_guess(&[0.0]).unwrap();
    let mut s = Cgmres::new(p, CgmresOptions::default()).unwrap();
    let x = [0.1, 0.2, 0.0, 0.0];
    s.initialize(0.0, &x, &guess, &InitOptions::default())
        .unwrap();
    let n = allocations(|| {
        for k in 0..200 {
            s.update(k as f64 * 1e-3, &x, 1e-3).unwrap();
        }
    });
    assert_eq!(n, 0, "Cgmres::update allocated {n} times");

    let mut c = NmpcController::new(
        Cgmres::new(
            InputBounds::new(Cartish, vec![InputBound::symmetric(0, 2.0, 0.01)]).unwrap(),
            CgmresOptions::default(),
        )
        .unwrap(),
        1e-3,
        guess,
        InitOptions::default(),
    )
    .unwrap();
    let mut u = [0.0];
    // Including the first call, which initialises the solver.
    let n = allocations(|| {
        for k in 0..200 {
            c.update(k as f64 * 1e-3, &x, &mut u);
        }
        c.reset();
        c.update(1.0, &x, &mut u);
    });
    assert_eq!(n, 0, "NmpcController::update allocated {n} times");
    assert_eq!(c.statistics().updates, 1);
}

#[test]
fn quantizer_sliding_mode_and_swing_up_controllers_do_not_allocate() {
    use pendulab_control::quantizer::{DynamicQuantizer, InputQuantizer, QuantizedController};
    use pendulab_control::sliding_mode::SlidingModeController;
    use pendulab_control::swing_up::{
        CartEnergyShaping, EnergyPumping, EnergyShapingGains, swing_up_then_balance,
    };
    use pendulab_lti::Mat;
    use pendulab_plants::{CartEquilibrium, CartPendulum};

    let plant = CartPendulum::book();
    let lin = plant.linearize(CartEquilibrium::upright()).unwrap();
    let smc =
        SlidingModeController::new(&[3.3, 14.7, 3.3, 2.1], lin.a(), lin.b(), 30.0, 5.0).unwrap();
    let taps = vec![Mat::from_element(1, 1, -0.5); 20];
    let q = DynamicQuantizer::fir(&taps, 1, 0.5).unwrap();
    let mut quantised = QuantizedController::new(smc.clone(), InputQuantizer::from(q)).unwrap();
    let mut switching = swing_up_then_balance(
        EnergyPumping::new(&plant, 0.8).unwrap(),
        smc,
        vec![(1, std::f64::consts::FRAC_PI_4)],
    )
    .unwrap();
    let mut shaping = CartEnergyShaping::new(&plant, EnergyShapingGains::cart_rig()).unwrap();
    let mut u = [0.0];
    let n = allocations(|| {
        for k in 0..500 {
            let t = k as f64 * 1e-3;
            // From hanging to upright and back: the switch happens inside the loop.
            let th = std::f64::consts::PI * (1.0 - k as f64 / 250.0);
            let y = [0.01, th, 0.1, -0.2];
            quantised.update(t, &y, &mut u);
            switching.update(t, &y, &mut u);
            shaping.update(t, &y, &mut u);
        }
    });
    assert_eq!(n, 0, "controllers allocated {n} times");
    assert_eq!(switching.switch_times().len(), 1);
}
