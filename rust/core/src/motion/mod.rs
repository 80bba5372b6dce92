mod law;
pub use law::*;
