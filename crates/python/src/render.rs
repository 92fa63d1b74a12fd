//! Pictures of the rigs for the environments' `render_mode="rgb_array"`: one frame of
//! `pendulab-plot`'s rig animation (the drawing the book's figures use) at the given state,
//! decoded to an `H × W × 3` `uint8` array. Rendering only: the state comes from the caller.

use numpy::{IntoPyArray, PyArray3, PyArrayMethods};
use pendulab_plot::{Animation, AnimationOptions, ArmGeometry, CartGeometry};
use pyo3::prelude::*;

use crate::errors::{Kind, new_err};

/// Adds this facet's function to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(render_rig, m)?)?;
    Ok(())
}

fn error(e: impl std::fmt::Display) -> PyErr {
    new_err(Kind::InvalidArgument, format!("render: {e}"), None)
}

/// `render_rig(rig, state, travel, pendulum_length=None, width=480, height=320)`: the rig
/// `"cart"` (state `[z, θ, ż, θ̇]`, the rail drawn over `±travel` m) or `"arm"` (state
/// `[θ₁, θ₂, θ̇₁, θ̇₂]`) at `state`, angles from the upward vertical, as an `(height, width, 3)`
/// `uint8` RGB array. `pendulum_length` (m) overrides the drawn pendulum's length (the
/// book's `L_p` = 0.38 m, `L₂` = 0.3 m by default).
#[pyfunction]
#[pyo3(signature = (rig, state, travel, pendulum_length = None, width = 480, height = 320))]
fn render_rig<'py>(
    py: Python<'py>,
    rig: &str,
    state: [f64; 4],
    travel: f64,
    pendulum_length: Option<f64>,
    width: u32,
    height: u32,
) -> PyResult<Bound<'py, PyArray3<u8>>> {
    let options = AnimationOptions {
        width,
        height,
        show_time: false,
        ..AnimationOptions::default()
    };
    let anim = match rig {
        "cart" => {
            let d = CartGeometry::default();
            let g = CartGeometry {
                rail: (-travel, travel),
                pendulum_length: pendulum_length.unwrap_or(d.pendulum_length),
                ..d
            };
            Animation::cart(&[0.0], &[state[0]], &[state[1]], g)
        }
        "arm" => {
            let d = ArmGeometry::default();
            let g = ArmGeometry {
                pendulum_length: pendulum_length.unwrap_or(d.pendulum_length),
                ..d
            };
            Animation::arm(&[0.0], &[state[0]], &[state[1]], g)
        }
        other => {
            return Err(error(format!(
                "rig {other:?}: expected \"cart\" or \"arm\""
            )));
        }
    }
    .map_err(error)?
    .options(options);
    let png = py.detach(|| anim.frame_png(0.0)).map_err(error)?;
    let decoder = png::Decoder::new(std::io::Cursor::new(png));
    let mut reader = decoder.read_info().map_err(error)?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| error("frame too large"))?;
    let mut buf = vec![0; size];
    let info = reader.next_frame(&mut buf).map_err(error)?;
    let (h, w) = (info.height as usize, info.width as usize);
    let channels = info.line_size / w;
    let rgb: Vec<u8> = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    rgb.into_pyarray(py).reshape([h, w, 3])
}
