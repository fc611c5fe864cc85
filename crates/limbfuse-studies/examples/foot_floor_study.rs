//! Where the walking simulator's foot meets the floor (y = 0) against the
//! contacts it places (heel strike at phase 0, toe off at 60 %; its
//! `--gait-reference` columns): per speed, the lowest heel and
//! metatarsal-head heights in each part of the stride (a negative height
//! is the contact point below the floor), the phase at which the heel
//! first reaches the floor around heel strike, and the last phase at which
//! the foot touches it around toe off (docs/SIMULATOR.md, "Known
//! limitations"; docs/RESULTS.md, "The simulated foot and the floor").
//! One stride without stride-to-stride variability or sensor errors,
//! out-of-plane motion as by default, 0.1 % phase steps.
//! `cargo run --release -p limbfuse-studies --example foot_floor_study`

use limbfuse_sim::gait_truth::STANCE_FRACTION;
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use limbfuse_studies::example_args::NoArgs;

/// Phase steps per stride.
const STEPS: usize = 1000;

/// Height (m) taken as on the floor: the stance foot's contact point stays
/// within 0.4 mm of it in single support (the Fourier fit's residual,
/// measured by this study), so 0.5 mm separates resting from lifting.
const ON_FLOOR_M: f64 = 5e-4;

/// Heights (m) of the heel and metatarsal head at stride fraction `s` (may
/// be negative or above 1: the stride before or after).
fn heights(sim: &WalkingSimulator, period: f64, s: f64) -> (f64, f64) {
    // one stride in, so that `s` < 0 is inside the trial
    let tr = sim.truth(period * (1.0 + s));
    (tr.contacts[0].p.y, tr.contacts[1].p.y)
}

fn main() {
    use clap::Parser;
    let _ = NoArgs::parse();
    println!(
        "| speed (m/s) | lowest heel / metatarsal head (mm): 0-10 % | 10-50 % | 50-60 % | 60-70 % | 70-100 % | heel reaches the floor (ms from the placed heel strike) | foot leaves the floor (ms from the placed toe off) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for speed in [0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8] {
        let sim = WalkingSimulator::new(WalkingConfig {
            speed_mps: speed,
            noise: false,
            variability: None,
            ..Default::default()
        })
        .expect("a speed within the simulator's range");
        let period = 1.0 / sim.stride_frequency();
        let parts = [
            (0.0, 0.1),
            (0.1, 0.5),
            (0.5, STANCE_FRACTION),
            (STANCE_FRACTION, 0.7),
            (0.7, 1.0),
        ];
        let mut lowest = [(f64::MAX, f64::MAX); 5];
        for i in 0..STEPS {
            let s = i as f64 / STEPS as f64;
            let (h, m) = heights(&sim, period, s);
            let p = parts
                .iter()
                .position(|(a, b)| s >= *a && s < *b)
                .unwrap_or(4);
            lowest[p] = (lowest[p].0.min(h), lowest[p].1.min(m));
        }
        // heel strike: the first phase of -20 %..+20 % with the heel on the
        // floor, searched from the swing's end side
        let heel_down = (0..=400)
            .map(|i| -0.2 + i as f64 / STEPS as f64)
            .find(|&s| heights(&sim, period, s).0 <= ON_FLOOR_M);
        // toe off: the last phase of 40-80 % with a contact point on
        // the floor
        let foot_up = (0..=400)
            .map(|i| 0.4 + i as f64 / STEPS as f64)
            .rev()
            .find(|&s| {
                let (h, m) = heights(&sim, period, s);
                h.min(m) <= ON_FLOOR_M
            });
        let ms = |d: Option<f64>| match d {
            Some(d) => format!("{:+.0}", d * period * 1e3),
            None => "none".into(),
        };
        let mm = |(h, m): (f64, f64)| format!("{:.1} / {:.1}", h * 1e3, m * 1e3);
        println!(
            "| {speed:.1} | {} | {} | {} | {} | {} | {} | {} |",
            mm(lowest[0]),
            mm(lowest[1]),
            mm(lowest[2]),
            mm(lowest[3]),
            mm(lowest[4]),
            ms(heel_down),
            ms(foot_up.map(|s| s - STANCE_FRACTION)),
        );
    }
}
