//! Synthesis (issue 35): mechanisms dimensioned from what they must do.
//!
//! Each kernel takes what a mechanism must do (precision points, target
//! points, poses, limits) as slices and returns the dimensions with their
//! margins; candidates are evaluated in parallel batches.

pub mod burmester;
pub mod cam_size;
pub mod dwell;
pub mod fourbar;
pub mod function;
pub mod motion;
pub mod path;
