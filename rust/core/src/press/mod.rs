mod criteria;
mod pareto;
pub use criteria::*;
pub use pareto::*;
