mod oscillator;
pub use oscillator::*;
