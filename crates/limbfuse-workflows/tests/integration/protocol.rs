//! The multi-start protocol of paper 001 against a hand-computed case, and
//! against running the filter by hand from each start.

use std::fmt;

use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimate, Estimator, EstimatorError, Outputs, Record, Sample, Segment};
use limbfuse_eval::TimeWindow;
use limbfuse_methods::segment_params::{FilterMethod, FilterParams, Preset};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use limbfuse_workflows::protocol::{multi_start, plan_intervals, slice_interval, StartPlan};

/// Outputs thigh = time since its first sample, trunk = 0.
#[derive(Default)]
struct Clock {
    first: Option<f64>,
}

impl Estimator for Clock {
    fn name(&self) -> &'static str {
        "clock"
    }
    fn outputs(&self) -> Outputs {
        Outputs::ALL_ANGLES
    }
    fn describe_parameters(&self, _out: &mut dyn fmt::Write) -> fmt::Result {
        Ok(())
    }
    fn reset(&mut self) {
        self.first = None;
    }
    fn step(&mut self, s: &Sample) -> Result<Estimate, EstimatorError> {
        let t0 = *self.first.get_or_insert(s.t);
        let mut e = Estimate::empty(s.t);
        e.set_segment(Segment::Thigh, s.t - t0);
        e.set_segment(Segment::Trunk, 0.0);
        Ok(e)
    }
}

#[test]
fn averaging_over_starts_matches_a_hand_computed_case() {
    // t = 0..6 s at 1 Hz; reference thigh = 0.5 t, trunk = 1.
    let records: Vec<Record> = (0..=6)
        .map(|k| {
            let mut r = Record::default();
            r.sample.t = k as f64;
            r.reference.segment[Segment::Thigh.index()] = Some(0.5 * k as f64);
            r.reference.segment[Segment::Trunk.index()] = Some(1.0);
            r
        })
        .collect();
    let plan = StartPlan {
        window: TimeWindow::parse("0:6").unwrap(),
        starts: 3,
        length_s: Some(2.0),
    };
    let iv = plan_intervals(&records, &plan).unwrap();
    assert_eq!(iv, vec![(0.0, 2.0), (2.0, 4.0), (4.0, 6.0)]);
    let make = || Ok(Box::new(Clock::default()) as Box<dyn Estimator>);
    let r = multi_start(&make, &records, &iv, false).unwrap();
    // Thigh error e = (t - s) - 0.5 t: start 0: 0, 0.5, 1 -> sqrt(5/12);
    // start 2: -1, -0.5, 0 -> sqrt(5/12); start 4: -2, -1.5, -1 -> sqrt(29/12).
    let thigh = (2.0 * (5.0f64 / 12.0).sqrt() + (29.0f64 / 12.0).sqrt()) / 3.0;
    let got = r.rmse(AngleChannel::Segment(Segment::Thigh)).unwrap();
    assert!((got - thigh).abs() < 1e-12, "{got} vs {thigh}");
    assert_eq!(r.rmse(AngleChannel::Segment(Segment::Trunk)), Some(1.0));
    assert_eq!(r.rmse(AngleChannel::Segment(Segment::Shank)), None);
    // Mean over the evaluated segments (trunk, thigh).
    assert!((r.mean_rmse().unwrap() - (1.0 + thigh) / 2.0).abs() < 1e-12);
    assert_eq!(r.n_samples(), 9);
    assert_eq!(
        r.max_abs_error(AngleChannel::Segment(Segment::Thigh)),
        Some(2.0)
    );
    let j = r.to_json();
    assert_eq!(j["starts"], 3);
    assert_eq!(j["start_times_s"], serde_json::json!([0.0, 2.0, 4.0]));
    assert!(
        (j["mean_rmse_deg"].as_f64().unwrap() - ((1.0 + thigh) / 2.0).to_degrees()).abs() < 1e-9
    );
    assert!(r.to_text().contains("starting points: 3"));
}

#[test]
fn each_start_is_a_fresh_filter_run_on_its_interval_only() {
    let records: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        duration_s: 12.0,
        imu_rate_hz: 50.0,
        seed: 4,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect();
    let params = FilterParams::preset(FilterMethod::Mjls, Preset::Default);
    let plan = StartPlan {
        window: TimeWindow::parse("2:12").unwrap(),
        starts: 4,
        length_s: None,
    };
    let iv = plan_intervals(&records, &plan).unwrap();
    assert_eq!(iv.len(), 4);
    // The 50 Hz trial ends at 11.98 s: the window is clipped there.
    assert!((iv[3].1 - 11.98).abs() < 1e-9 && (iv[0].1 - iv[0].0 - 4.99).abs() < 1e-9);
    let make = || {
        params
            .build()
            .map(|f| f as Box<dyn Estimator>)
            .map_err(|e| e.to_string())
    };
    let r = multi_start(&make, &records, &iv, false).unwrap();
    // By hand: the mean over starts of each run's RMSE.
    let mut sum = [0.0; 4];
    for &(s, e) in &iv {
        let mut f = params.build().unwrap();
        let (mut sq, mut n) = ([0.0; 4], [0usize; 4]);
        let recs = slice_interval(&records, s, e);
        for rec in recs {
            let est = f.step(&rec.sample).unwrap();
            for i in 0..4 {
                // (a segment waiting for its start has no estimate and is not scored)
                if let Some(x) = est.segment[i] {
                    let d = x - rec.reference.segment[i].unwrap();
                    sq[i] += d * d;
                    n[i] += 1;
                }
            }
        }
        for i in 0..4 {
            sum[i] += (sq[i] / n[i] as f64).sqrt() / iv.len() as f64;
        }
    }
    for s in Segment::ALL {
        let got = r.rmse(AngleChannel::Segment(s)).unwrap();
        assert!(
            (got - sum[s.index()]).abs() < 1e-12,
            "{s:?}: {got} vs {}",
            sum[s.index()]
        );
    }
    // Deterministic whatever the thread count.
    let again = multi_start(&make, &records, &iv, false).unwrap();
    assert_eq!(again, r);
}
