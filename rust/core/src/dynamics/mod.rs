//! Machine dynamics (issue 34): the frame's shaking force and moment and the
//! balancing of linkages by counterweights ([`shaking`]).
//!
//! Files: this door and one file per subject.

pub mod shaking;
