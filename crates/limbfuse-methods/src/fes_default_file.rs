//! The commented default parameter files of `sdre`, `ekf`, `rmx` and
//! `knee-kinematic` (`limbfuse params --method NAME`).

use limbfuse_estimators::fes::fixed_hip::fixed_hip_default_tuning;
use limbfuse_estimators::fes::knee::knee_default_tuning;
use limbfuse_estimators::fes::knee_extended::kinematic_default_tuning;
use limbfuse_estimators::fes::mahony::MahonyGains;
use limbfuse_estimators::fes::Linearisation;

use crate::MethodName;

/// The default parameter file of `sdre`, `ekf` or `rmx`, commented
/// (`limbfuse params --method NAME`). The model and the default tuning come
/// from the trial's `# model:` metadata, so they are listed as comments.
pub fn default_file(method: MethodName) -> String {
    use std::fmt::Write as _;
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut s = format!(
        "# limbfuse {method} parameters (paper 004; docs/FES_ESTIMATION.md).\n\
         # The model comes from the trial's `# model:` / `# subject:` / `# param.*` lines;\n\
         # every key below overrides it.\n\
         method = \"{method}\"\n\n"
    );
    if method == MethodName::KneeKinematic {
        let t = kinematic_default_tuning();
        let _ = write!(
            s,
            "[measurement]\n# shank_imu_m = 0.2  # accelerometer below the knee (m); default: the trial's # shank_imu_m\n\
             # (or # param_r_imu), else 0.5 x 0.246 x height (Winter 2009)\n\n\
             [tuning]  # states: shank angle, rate, angular acceleration, gyro bias, acc bias\n\
             # q = [{}]  s = [{}]  p0 = [{}]  max_substep = {:?}\n",
            list(t.q.as_slice()),
            list(t.s.as_slice()),
            list(t.p0.as_slice()),
            t.max_substep
        );
        return s;
    }
    if method == MethodName::Rmx {
        let g = MahonyGains::default();
        let _ = write!(
            s,
            "[rmx]  # Mahony gains\nkp = {:?}  # 1/s\nki = {:?}  # 1/s^2\n",
            g.kp, g.ki
        );
        return s;
    }
    let lin = if method == MethodName::Sdre {
        Linearisation::Sdc
    } else {
        Linearisation::Jacobian
    };
    let knee = knee_default_tuning(lin);
    let hip = fixed_hip_default_tuning(lin);
    let _ = writeln!(
        s,
        "[model]  # e.g. inertia = 0.45 (knee-fes keys: inertia, mass, l_c, g, phi0, theta_eq, t_a, d1-d6, c0-c3, i_threshold_ma, i_saturation_ma)\n"
    );
    let _ = writeln!(
        s,
        "[tuning]  # defaults per model; uncomment to override\n\
         # knee-fes:  q = [{}]  s = [{}]  a = {:?}  p0 = [{}]  max_substep = {:?}\n\
         # fixed-hip: q = [{}]  s = [{}]  a = {:?}  p0 = [{}]  max_substep = {:?}",
        list(knee.q.as_slice()),
        list(knee.s.as_slice()),
        knee.a,
        list(knee.p0.as_slice()),
        knee.max_substep,
        list(hip.q.as_slice()),
        list(hip.s.as_slice()),
        hip.a,
        list(hip.p0.as_slice()),
        hip.max_substep,
    );
    let _ = writeln!(
        s,
        "\n[states]  # issue 16; each adds a state, default false (fixed-hip: activation only); without this\n\
         # table, a [model] that states t_a gets activation, gyro_bias and acc_bias (the plant\n\
         # as stated; `activation = false` here gives the thesis estimator)\n\
         # activation = true   # a_ke' = (u_ke - a_ke) / T_a, T_a = [model] t_a\n\
         # disturbance = true  # unknown knee torque (N m), random walk\n\
         # gyro_bias = true    # shank gyro z bias (rad/s)\n\
         # acc_bias = true     # shank accelerometer x bias (m/s^2)\n\
         # With states, [tuning] q and p0 have one value per state: x1, x2, then the\n\
         # enabled ones in this order (defaults from physics: docs/FES_ESTIMATION.md).\n\
         # With states, [tuning] torque_error = 0.1 sets how much the filter trusts the\n\
         # model (it admits a torque error of e m g l_c); `limbfuse tune --method sdre`\n\
         # chooses it on a pre-trial.\n\n\
         [measurement]\n\
         # shank_imu_m = 0.2  # accelerometer below the knee (m): acc_x = g sin x1 + r x1''; default 0 (thesis);\n\
         # with t_a and no [states]: the trial's # shank_imu_m (or # param_r_imu), else 0.5 x 0.246 x height (Winter 2009)"
    );
    s
}
