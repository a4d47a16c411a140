//! Gear trains built from geardyn's pair physics.
//!
//! A train is a set of rigid **bodies** (gears, a carrier, shafts' ends) that turn about their
//! axes, joined by **meshes** (an external or internal spur pair of mean stiffness from the
//! potential-energy method, possibly between gears whose axes ride on a carrier), **shafts**
//! (torsional springs between two bodies) and **supports** (a body held fixed or on a torsional
//! spring), with an input and an output body ([`description`]). Built-in trains
//! ([`presets`]): a planetary stage (sun input, carrier output, fixed ring, equally spaced
//! planets, mesh phases from the geometry), a two-stage drive on an elastic intermediate shaft,
//! and the single pair written as a train.
//!
//! What a train gives today: its rigid-body **kinematics** (the speed of every body for a given
//! input speed, mesh frequencies; [`kinematics`]), its **linear model** of mean stiffness
//! ([`linear`]) and its **modes** (natural frequencies, mode shapes, each typed rigid-body,
//! rotational or planet mode with its multiplicity; [`modes`]), and the **Campbell** diagram's
//! resonances (mesh harmonics crossing natural frequencies over the input speed; [`campbell`]).
//!
//! Conventions: dimensional SI units in computations (rad, N m/rad, kg m², Hz), the description's
//! fields carry their unit in their names (`_mm`, `_kgm2`, `_n_per_m`). Rotations are absolute
//! angles, all counted in one sense (counter-clockwise seen from the input side). The model is
//! purely torsional: bearings are rigid, so every body keeps its axis (a planet's axis turns
//! with the carrier at its orbit radius); translations of the central members (Lin & Parker's
//! 3-degree-of-freedom bodies) are not modelled.

pub mod campbell;
pub mod description;
pub mod dynamics;
pub mod error;
pub mod fault;
pub mod kinematics;
pub mod linear;
pub mod modes;
pub mod operating;
pub mod presets;

pub use description::{Body, Load, Mesh, Shaft, Support, TrainSpec};
pub use error::TrainError;
pub use modes::{Mode, ModeKind, Modes};
