//! The front ends' tunables in one place: each number the driver, the outputs, the recording,
//! the fit and the explorer chose rather than derived, with its meaning, unit and source. None of
//! them changes a result of the physics (the solver's own are `decohesion_physics::tunables`);
//! they set how often files are written, how much memory waits, how a picture is framed and how
//! the explorer shares its time. The modules that use them re-export them under their old paths.
//!
//! The sources, as in the solver's module: **chosen** (a design value with no measurement behind
//! it), **limit** (a bound on memory or time, so that a long run cannot exhaust either), or
//! **external** (a fact of another program this one must match, named where it is stated).

use std::time::Duration;

// ---------------------------------------------------------------------------------------------
// The run driver's outputs (`run/src/output/`, `run/src/outputs/`).

/// Memory that frames waiting for an output's writer thread may take before the solver waits
/// (back-pressure) [bytes]. Source: limit.
pub const QUEUE_BYTES: usize = 64 << 20;

/// Default number of frames over the scene's `end_time` (`output::Cadence::Default`) [1].
/// Source: chosen.
pub const DEFAULT_FRAMES: f64 = 200.0;

/// The time series file (`--series`): rows are written to the file once this many bytes of
/// whole lines wait… [bytes]. Source: chosen.
pub const SERIES_FLUSH_BYTES: usize = 64 << 10;

/// …or this much wall time after the last write, so a file being followed (`tail -f`) lags
/// little and a killed process loses at most this much [s]. Source: chosen.
pub const SERIES_FLUSH_WALL: Duration = Duration::from_millis(250);

/// Margin of a half-space's drawn square beyond the body's bounding box projected on it, as a
/// fraction of the body's largest extent [1]. Source: chosen.
pub const HALF_SPACE_MARGIN: f64 = 0.15;

// ---------------------------------------------------------------------------------------------
// The Rerun recording (`run/src/record/`).

/// Buffered frames are sent at least every this many frames… [frames]. Source: chosen.
pub const RECORD_FLUSH_ROWS: usize = 1000;

/// …or when they take this much memory… [bytes]. Source: limit.
pub const RECORD_FLUSH_BYTES: usize = 16 << 20;

/// …or after a tenth of the wall time the run has taken so far, between
/// [`RECORD_FLUSH_WALL_MIN`] and this (the lag of a live viewer): short runs encode beside the
/// solver rather than all at the end, long runs do not make thousands of small chunks [s].
/// Source: chosen.
pub const RECORD_FLUSH_WALL: Duration = Duration::from_millis(500);

/// The shortest wall time between two flushes of the recording [s]. Source: chosen.
pub const RECORD_FLUSH_WALL_MIN: Duration = Duration::from_millis(10);

/// Interfaces with at most this many nodes get one α(t) series per node (paper fig. 6 left)
/// [nodes]. Source: chosen.
pub const ALPHA_PER_NODE_MAX: usize = 64;

/// Longest traction arrow, drawn for the peak traction T_max of the law, as a fraction of the
/// body's largest extent [1]. Source: chosen.
pub const ARROW_FRACTION: f64 = 0.2;

/// Length of a contact normal arrow (the mould's unit normal at a node in contact), as a
/// fraction of the body's largest extent [1]. Source: chosen.
pub const NORMAL_FRACTION: f64 = 0.08;

/// Vertical field of view of the viewer's 3-D eye [degrees]. Source: external
/// (`Eye::DEFAULT_FOV_Y` of Rerun's `re_view_spatial`, which the blueprint cannot set).
pub const EYE_FOV_Y_DEG: f64 = 55.0;

/// The narrowest width / height the 3-D view is framed for: in the default layout it takes the
/// left half of the window (1560 × 960 in the screenshots: 0.87), so the horizontal field of
/// view is the narrower one [1]. Source: chosen.
pub const EYE_ASPECT_MIN: f64 = 0.75;

/// The eye's elevation above the horizontal plane (z is up in every scene): the body is seen
/// from above its side, the interface below it through the gap to the mould [degrees].
/// Source: chosen.
pub const EYE_ELEVATION_DEG: f64 = 30.0;

/// A mould's drawing counts as near the body within this fraction of the body's largest extent
/// around its bounding box; farther parts (a long plate, a large mould) are not framed [1].
/// Source: chosen.
pub const EYE_NEAR_FRACTION: f64 = 0.5;

/// Margin on the distance that fits the framed box's bounding sphere in the field of view [1].
/// Source: chosen.
pub const EYE_MARGIN: f64 = 1.05;

/// Widest span of ticks the viewer plots whole [ticks]. Source: external: on a sequence
/// timeline whose data span more than 2000 ticks, Rerun 0.36's time-series views open on the
/// time cursor ± 1000 (`re_view_time_series` fallbacks), which would cut a three-decade sweep
/// at 1000 per decade to its last decade.
pub const SWEEP_WHOLE_SPAN: f64 = 2000.0;

// ---------------------------------------------------------------------------------------------
// The fit (`run/src/fit/`).

/// Default of `--max-evals` [runs]. Source: limit.
pub const FIT_MAX_EVALS: usize = 600;

/// Default of `--tolerance`: misfits within 1e-10 of each other (relative RMS residuals within
/// about 1e-5) are one [1]. Source: chosen.
pub const FIT_TOLERANCE: f64 = 1e-10;

/// Nelder–Mead restarts at most (after the first descent) [1]. Source: limit.
pub const FIT_MAX_RESTARTS: usize = 20;

/// Step of the σ's central differences, in the search variable z: 1 % of each key's searched
/// range [1]. Source: chosen.
pub const FIT_JACOBIAN_STEP: f64 = 0.01;

// ---------------------------------------------------------------------------------------------
// The explorer (`src/gui/`, native and the web page).

/// Above this many elements the window does not estimate h_crit while settings are edited (the
/// set-up and the Lanczos estimate would hold the window for a visible time); the run does it
/// [elements]. Source: chosen.
pub const CHECK_MAX_ELEMENTS: usize = 25_000;

/// Wall time a run in the page steps per frame before the frame is drawn: the page stays
/// responsive (≥ ~40 frames per second with the drawing) and Stop acts at the next frame [s].
/// Source: chosen.
pub const FRAME_BUDGET: Duration = Duration::from_millis(10);

/// The solver's time per unit of the page's drawing time, when drawing is slow
/// (`gui::page_run::PageRun::advance`) [1]. Source: chosen.
pub const DRAWING_RATIO: u32 = 4;

/// The longest slice of steps between two pictures of the page when drawing is slow: Stop still
/// acts within about this much [s]. Source: chosen.
pub const MAX_SLICE: Duration = Duration::from_millis(500);

/// The most memory a run's 3-D frames take in the explorer [bytes]. Source: limit.
pub const MAX_RUN_BYTES: usize = 64 << 20;

/// Most samples of a run's curve the explorer keeps (72 bytes each, in memory and in the saved
/// history) [samples]. Source: limit.
pub const CURVE_MAX_POINTS: usize = 1024;

/// Frame times kept for the 3-D view's frame-rate label [frames]. Source: chosen.
pub const FRAME_TIMES: usize = 60;

/// A click selects the node drawn nearest to it within this distance [points]. Source: chosen.
pub const PICK_RADIUS: f32 = 12.0;

/// Vertical field of view of the explorer's 3-D camera [rad]. Source: chosen.
pub const FOV_Y: f32 = 0.6;

/// The zoom of the projector mode (egui's points per pixel, × the system's) [1]. Source: chosen.
pub const PROJECTOR_ZOOM: f32 = 1.5;

/// The width of plot lines in the projector mode (egui_plot's default is 1.5) [points].
/// Source: chosen.
pub const PROJECTOR_LINE: f32 = 3.5;

/// The share of the frame's width the lesson's text takes in the embeddable view, and the 3-D
/// view's (the plots have the rest, a plot a row in an 800-point frame): the picture keeps at
/// least 40 % of the frame's width with the panel's margins [1]. Source: chosen.
pub const EMBED_LESSON_WIDTH: f32 = 0.30;
/// See [`EMBED_LESSON_WIDTH`] [1].
pub const EMBED_VIEW_WIDTH: f32 = 0.44;

/// At most this many of the run's frames go into an animation (evenly spread, the last one
/// included) [frames]. Source: limit.
pub const GIF_FRAMES: usize = 60;

/// Delay between the animation's frames [1/100 s]. Source: chosen.
pub const GIF_DELAY: u16 = 10;

/// A capture wider than this is halved for the animation [pixels]. Source: limit.
pub const GIF_MAX_WIDTH: usize = 480;
