//! Errors of the book examples.

/// Why an example could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BookError {
    /// No example has this id.
    #[error("unknown example id '{0}' (see `pendulab book list`)")]
    UnknownId(String),
    /// The example needs measured data that was not given.
    #[error("example '{id}' needs measured data: {what} (pass it with --data FILE.csv)")]
    NeedsData {
        /// Example id.
        id: String,
        /// What data, with the expected columns.
        what: String,
    },
    /// A computation inside the example failed.
    #[error("example '{id}': {source}")]
    Computation {
        /// Example id.
        id: String,
        /// What failed: the toolkit's error or a check of the example's own.
        source: Box<Cause>,
    },
    /// A figure or an animation could not be drawn or rendered.
    #[error("example '{id}': cannot draw figure {stem}: {source}")]
    Figure {
        /// Example id.
        id: String,
        /// File stem of the figure ([`crate::Graphic::stem`]).
        stem: String,
        /// The plot crate's error.
        source: pendulab_plot::PlotError,
    },
    /// A front end could not write a figure's file (the book itself writes none).
    #[error("example '{id}': cannot write figure {}: {source}", path.display())]
    WriteFigure {
        /// Example id.
        id: String,
        /// Path of the file or directory.
        path: std::path::PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The example panicked (caught by the front end that ran it).
    #[error("example '{id}': panicked: {payload}")]
    Panicked {
        /// Example id.
        id: String,
        /// The panic's message.
        payload: String,
    },
}

/// What failed inside an example ([`BookError::Computation`]): the error of the toolkit crate
/// that failed, shown as that crate words it, or a check of the example's own.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Cause {
    /// Linear systems, matrix equations, designs (`pendulab-lti`).
    #[error(transparent)]
    Lti(#[from] pendulab_lti::LtiError),
    /// LMI/SOS modelling and solving (`pendulab-lmi`).
    #[error(transparent)]
    Lmi(#[from] pendulab_lmi::LmiError),
    /// Simulation, sensors, actuators, controllers at run time (`pendulab-sim`).
    #[error(transparent)]
    Sim(#[from] pendulab_sim::SimError),
    /// Plant parameters and linearisation (`pendulab-plants`).
    #[error(transparent)]
    Plant(#[from] pendulab_plants::PlantError),
    /// Controller designs beyond a static gain (`pendulab-control`).
    #[error(transparent)]
    Control(#[from] pendulab_control::ControlError),
    /// Identification from data (`pendulab-ident`).
    #[error(transparent)]
    Ident(#[from] pendulab_ident::IdentError),
    /// A figure's layout (`pendulab-plot`), where a figure's numbers are part of the result.
    #[error(transparent)]
    Plot(#[from] pendulab_plot::PlotError),
    /// A check of the example's own failed: what was expected, and what happened.
    #[error("{0}")]
    Check(String),
}

impl From<&str> for Cause {
    fn from(what: &str) -> Self {
        Cause::Check(what.to_string())
    }
}

impl From<String> for Cause {
    fn from(what: String) -> Self {
        Cause::Check(what)
    }
}
