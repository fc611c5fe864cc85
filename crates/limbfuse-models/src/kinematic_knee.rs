//! A model-free kinematic model of the shank (issue 16, the fair baseline
//! for the knee-FES models; docs/FES_ESTIMATION.md "Kinematic baseline"):
//! no muscle, no gravity torque, only kinematics and the sensor errors.
//!
//! State `x = [x1, x2, x3, b_g, b_a]`: shank angle from hanging (rad), its
//! rate (rad/s) and angular acceleration (rad/s^2), the shank gyro z bias
//! (rad/s) and accelerometer x bias (m/s^2).
//!
//! * `x1' = x2`, `x2' = x3`, `x3' = 0` (angular jerk is the process noise),
//!   `b_g' = 0`, `b_a' = 0` (random walks);
//! * `y = [x2 + b_g, g sin x1 + r x3 + b_a]` (gyro; accelerometer `r` metres
//!   below the knee: gravity plus the tangential acceleration).
//!
//! SDC: `A` is the constant chain matrix, `C = [[0, 1, 0, 1, 0],
//! [g sinc x1, 0, r, 0, 1]]`, no input.

use nalgebra::{SMatrix, SVector};

use crate::error::{finite, positive, ModelError};
use crate::sdc::{sinc, SdcModel};

/// The kinematic shank model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KinematicKneeModel {
    /// Gravity (m/s^2).
    pub g: f64,
    /// Shank accelerometer distance below the knee `r` (m).
    pub imu_radius: f64,
}

impl KinematicKneeModel {
    /// The model; `g` positive, `imu_radius` finite.
    pub fn new(g: f64, imu_radius: f64) -> Result<Self, ModelError> {
        positive("g", g)?;
        finite("imu_radius", imu_radius)?;
        Ok(KinematicKneeModel { g, imu_radius })
    }
}

impl SdcModel<5, 2, 0> for KinematicKneeModel {
    fn f(&self, x: &SVector<f64, 5>, _: &SVector<f64, 0>) -> SVector<f64, 5> {
        SVector::<f64, 5>::new(x[1], x[2], 0.0, 0.0, 0.0)
    }

    fn h(&self, x: &SVector<f64, 5>) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(
            x[1] + x[3],
            self.g * libm::sin(x[0]) + self.imu_radius * x[2] + x[4],
        )
    }

    fn sdc_a(&self, _: &SVector<f64, 5>) -> SMatrix<f64, 5, 5> {
        let mut a = SMatrix::<f64, 5, 5>::zeros();
        a[(0, 1)] = 1.0;
        a[(1, 2)] = 1.0;
        a
    }

    fn input_term(&self, _: &SVector<f64, 5>, _: &SVector<f64, 0>) -> SVector<f64, 5> {
        SVector::zeros()
    }

    fn sdc_c(&self, x: &SVector<f64, 5>) -> SMatrix<f64, 2, 5> {
        let mut c = self.jacobian_h(x);
        c[(1, 0)] = self.g * sinc(x[0]);
        c
    }

    fn jacobian_f(&self, x: &SVector<f64, 5>, _: &SVector<f64, 0>) -> SMatrix<f64, 5, 5> {
        self.sdc_a(x)
    }

    fn jacobian_h(&self, x: &SVector<f64, 5>) -> SMatrix<f64, 2, 5> {
        let mut c = SMatrix::<f64, 2, 5>::zeros();
        c[(0, 1)] = 1.0;
        c[(0, 3)] = 1.0;
        c[(1, 0)] = self.g * libm::cos(x[0]);
        c[(1, 2)] = self.imu_radius;
        c[(1, 4)] = 1.0;
        c
    }
}
