mod cycle_ratio;
mod event_graph;
pub use cycle_ratio::*;
pub use event_graph::*;
