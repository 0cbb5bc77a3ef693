//! Motion sequences (`strand motion`): the table of one row per pose
//! ([`motion_csv`]), the events between poses ([`doc_events`]), the swept envelope of
//! the hoses ([`envelope_obj`]) and the plot of the outputs against the motion
//! parameter ([`motion_svg`]), and the worst pose of each quantity ([`worst_poses`]).

mod envelope;
mod events;
mod plot;
mod table;
mod worst;

pub use envelope::{Envelope, envelope_obj, envelope_of};
pub use events::{MotionEventRecord, doc_events, events_csv};
pub use plot::motion_svg;
pub use table::{MotionRow, motion_csv};
pub use worst::{Worst, WorstKind, worst_poses};
