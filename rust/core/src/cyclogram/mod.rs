//! Longest-path event scheduling on a network cyclogram.
//!
//! A cyclogram within one machine cycle is a directed acyclic graph: events are
//! vertices, operations are arcs `x -> y` with a phase angle `w` (degrees of
//! main-shaft rotation, negative for overlapping operations). The earliest
//! occurrence angle of every event is
//!
//! ```text
//! p(y) = 0                                  if y has no incoming arcs,
//! p(y) = max over arcs (x, y) of p(x) + w   otherwise,
//! ```
//!
//! computed in one pass over a topological order. [`EventGraph`] analyses the
//! structure once (topological order, events renumbered by their position in it,
//! incoming and outgoing arc lists stored by position, all in O(V + E)) and then
//! evaluates any number of weight vectors against it.
//!
//! [`max_difference`] and [`max_difference_batch`] solve the other problem a
//! cyclogram poses once cycles are allowed: the largest `x[t] - x[s]` subject to
//! difference constraints `x[dst] - x[src] <= w`, i.e. the optimum of a cyclogram
//! LP, by Bellman–Ford shortest paths (negative weights and cycles allowed).
//!
//! Files: `graph` (the arcs' checks, the domain's error, topological order),
//! `layout` (a network renumbered by topological position, built in linear
//! time), `event_graph` (longest paths on a prepared network), `difference`
//! (systems of difference constraints) and `cycle_ratio` (maximum cycle ratio and
//! the speed limit of a cyclic schedule).

mod cycle_ratio;
mod difference;
mod event_graph;
#[cfg(test)]
mod event_graph_tests;
mod graph;
mod layout;
#[cfg(test)]
mod order_tests;
mod speed_limit;
#[cfg(test)]
mod tests;

pub use cycle_ratio::{max_cycle_ratio, max_speed, CycleRatio, SpeedLimit, MIN_DIVISOR};
pub use difference::{max_difference, max_difference_batch, DIFFERENCE_RTOL};
pub use event_graph::{longest_path, Analysis, EventGraph};
pub use graph::{CyclogramError, MAX_ABS_VALUE, MAX_SIZE};
pub use speed_limit::{
    solve_proportional_into, speed_limits_proportional, ProportionalNetwork, SolveOut, SpeedSearch,
    PROPORTIONAL_MAX_DEG, PROPORTIONAL_MIN_DEG,
};
