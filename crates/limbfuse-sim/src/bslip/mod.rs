//! B-SLIP gait library generation and trial simulation (paper 003 sec II).

pub mod integrator;
pub mod library;
pub mod periodic;
pub mod search;
pub mod step;
pub mod step_law;
pub mod trial;
pub mod walker;
