//! Loaded tooth contact between the cycloid disc and the pins (docs/model.md sections 3 and 4).
//!
//! - [`law`]: Hertz line contact of a pin (radius `rrp`) on the disc flank: half-width, maximum
//!   pressure (Johnson, *Contact Mechanics*, 1985, eq 4.43) and the approach laws (paper eqs
//!   6-7 with the Hertz half-width, Johnson's form, or a linear spring).
//! - [`pin`]: the gap of every pin measured exactly on the actual (modified, worn) profile by
//!   projecting the pin centre on it, at a given disc pose.
//! - [`gap`]: the contact geometry of a worn flank that the static and dynamic analyses share,
//!   the gap field (exact global closest points tabulated over the mesh angle and averaged over
//!   the Hertz band).
//! - `elastic` (built with the tests): non-Hertzian line contact on a flank of any shape, the
//!   oracle that checks the gap field's band averaging.
//! - [`li`]: Li Lixing's closed-form load distribution (paper eqs 5, 9, 10).
//!
//! Sign conventions: a positive disc torque `T_disc` turns the disc counter-clockwise against
//! the pins of the flank `0 < mesh angle < pi`. The lever arm `l_j = (p_c x n)_z` of pin `j`
//! (contact point `p_c` from the disc centre, outward normal `n`) is positive on that flank;
//! the pin pushes on the disc with the moment `-F_j l_j`.

#[cfg(test)]
pub(crate) mod elastic;
pub mod gap;
pub mod law;
pub mod li;
pub mod pin;
pub mod pin_turning;

pub(crate) use law::PreparedLaw;
pub use law::{ApproachLaw, ContactModel, Groove, HertzState, Materials, PinBending};
pub(crate) use li::li_load_distribution;
pub(crate) use pin::pin_geometry;
pub use pin::{DiscPose, PinGeometry};
pub use pin_turning::PinTurning;
