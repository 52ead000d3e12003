//! A stop request (what SIGINT, SIGTERM or Ctrl-C in Python raise) is seen by every
//! engine at its next event or step: `advance_to` returns at once, with the state whole,
//! and a run that goes on afterwards is bitwise the run that was never stopped.
//!
//! The request is process-wide, so this file holds one test (a test binary of its own).

use emdstar_engines::{AnyEngine, EngineKind, EngineOptions};
use emdstar_system::{Config, stop};

const GAS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tests/md/configs/gas_small.toml"
);

fn engine(kind: EngineKind) -> AnyEngine {
    let config = Config::from_file(GAS.as_ref()).unwrap();
    let system = config.build().unwrap();
    let options = EngineOptions {
        engine: kind,
        ..Default::default()
    };
    AnyEngine::build(&options, &config, system, 1.0 / 50.0).unwrap()
}

#[test]
fn every_engine_stops_at_its_next_event_or_step_and_goes_on_as_if_never_stopped() {
    for kind in [
        EngineKind::Md,
        EngineKind::Emd,
        EngineKind::EmdStar,
        EngineKind::Hybrid,
    ] {
        let mut through = engine(kind);
        through.sim_mut().advance_to(0.01).unwrap();
        let mut stopped = engine(kind);
        stopped.sim_mut().advance_to(0.004).unwrap();
        let (t, work) = (stopped.sim().time(), stopped.sim().steps_done());
        stop::request(2);
        stopped.sim_mut().advance_to(0.01).unwrap();
        assert_eq!(
            (stopped.sim().time(), stopped.sim().steps_done()),
            (t, work),
            "{kind:?} went on after the stop request"
        );
        stop::clear();
        stopped.sim_mut().advance_to(0.01).unwrap();
        assert_eq!(stopped.sim().time(), through.sim().time(), "{kind:?}");
        assert!(
            stopped.sim().save_state() == through.sim().save_state(),
            "{kind:?}: the stopped run went on elsewhere"
        );
    }
}
