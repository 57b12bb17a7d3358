//! Planar rigid-body mechanics in absolute coordinates.
//!
//! Every body i has generalised coordinates qᵢ = (xᵢ, yᵢ, φᵢ): the centre of mass and the
//! orientation of the body x-axis. Ideal joints and drivers are constraint rows Φ(q, t) = 0
//! (`constraints.rs`, with the driver motions θ(t) in `drivers.rs`); applied forces give the generalised force vector Q (`forces.rs`).
//!
//! # References
//! 1. P. E. Nikravesh, *Computer-Aided Analysis of Mechanical Systems*, Prentice Hall, 1988, ch. 3–6.
//! 2. E. J. Haug, *Computer Aided Kinematics and Dynamics of Mechanical Systems*, Allyn & Bacon, 1989.

pub mod constraints;
pub mod drivers;
pub mod forces;
pub mod planar;

pub use constraints::{ConstraintRow, ConstraintSet, RowSource};
pub use forces::AppliedForces;
