mod solve;
mod triad;
pub use solve::*;
pub use triad::Triad;
