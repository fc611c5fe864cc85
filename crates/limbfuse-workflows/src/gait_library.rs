//! A built B-SLIP gait library (paper 003) as its file record
//! (`limbfuse gait-library build`): each gait's parameters, template timing
//! and sampled phase trajectories.

use limbfuse_io::gait_library::{
    BodyRecord, GaitLibraryFile, GaitRecord, PhaseTrajectories, SearchRecord, XiRecord, FORMAT,
    VERSION,
};
use limbfuse_models::bslip::BslipParams;
use limbfuse_sim::bslip::library::{lateral_excursion, LibraryGait};
use limbfuse_sim::bslip::search::SearchSettings;
use limbfuse_sim::bslip::walker::sample_step;

/// The file record of a built library.
pub fn gait_library_file(body: &BslipParams, lib: &[LibraryGait]) -> GaitLibraryFile {
    let s = SearchSettings::default();
    GaitLibraryFile {
        format: FORMAT.into(),
        version: VERSION,
        body: BodyRecord {
            mass: body.mass,
            rest_length: body.rest_length,
            gravity: body.gravity,
        },
        search: SearchRecord {
            k_max: s.k_max,
            stiffness_weight: s.stiffness_weight,
            periodic_tol: s.periodic_tol,
        },
        gaits: lib
            .iter()
            .map(|g| {
                let t = g.template(body);
                let rows = sample_step(&t, 0.01);
                let x = g.gait;
                GaitRecord {
                    speed: g.speed,
                    xi: XiRecord {
                        phi: x.phi,
                        theta: x.theta,
                        stiffness: x.stiffness,
                        height: x.height,
                        lateral: x.lateral,
                        forward_speed: x.forward_speed,
                    },
                    rest_length: body.rest_length,
                    step_length: t.step_length,
                    step_width: t.step_width,
                    step_time: t.step_time,
                    t_touchdown: t.t_touchdown,
                    t_lift_off: t.t_lift_off,
                    periodicity_residual: g.residual,
                    vertical_excursion: g.vertical_excursion(),
                    lateral_excursion: lateral_excursion(&t, &rows),
                    trajectory: {
                        let [ss1, ds, ss2] = rows;
                        PhaseTrajectories { ss1, ds, ss2 }
                    },
                }
            })
            .collect(),
    }
}
