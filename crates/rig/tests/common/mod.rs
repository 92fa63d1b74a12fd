//! What a front end does with a controller file, for the tests: `pendulab_rig::config::load`
//! reads and checks the file, `pendulab_control::spec::build` builds its controller (as
//! `pendulab rig run` does).
// Each test binary uses a different part of the helper.
#![allow(dead_code)]

use pendulab_control::spec::build;
use pendulab_rig::config::{self, Loaded};
use pendulab_sim::Controller;

/// A controller file loaded and its controller built.
pub struct Ready {
    /// The file's settings and spec.
    pub loaded: Loaded,
    /// The controller built from the spec.
    pub controller: Box<dyn Controller>,
    /// The pendulum angle the controller stabilises \[rad\].
    pub pendulum_centre: f64,
}

impl std::ops::Deref for Ready {
    type Target = Loaded;
    fn deref(&self) -> &Loaded {
        &self.loaded
    }
}

impl std::ops::DerefMut for Ready {
    fn deref_mut(&mut self) -> &mut Loaded {
        &mut self.loaded
    }
}

impl std::fmt::Debug for Ready {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ready")
            .field("loaded", &self.loaded)
            .finish_non_exhaustive()
    }
}

/// Loads the controller file `text` and builds its controller; either error as its message.
pub fn load(text: &str) -> Result<Ready, String> {
    let loaded = config::load(text).map_err(|e| e.to_string())?;
    let built = build(&loaded.spec, loaded.plant, loaded.ts).map_err(|e| e.to_string())?;
    Ok(Ready {
        loaded,
        controller: built.controller,
        pendulum_centre: built.pendulum_centre,
    })
}
