mod common;
use common::{scene, seeded_runner};
use twocars::num::fixed::Fixed;
use twocars::{Scalar, Status};
#[test]
fn worst() {
    let mut worst: Vec<(f64, String)> = Vec::new();
    let cell = std::cell::RefCell::new(&mut worst);
    seeded_runner(20_000).run(&scene(20.0), |s| {
        let o = s.observation();
        let a = twocars::evaluate_observation::<f64>(&o, twocars::Variant::Paper);
        let b = twocars::evaluate_observation::<Fixed>(&o, twocars::Variant::Paper);
        if a.status != Status::Ok || b.status != Status::Ok { return Ok(()); }
        let (ra, rb) = (a.report.unwrap(), b.report.unwrap());
        let near = ra.pairs.iter().flatten().flatten().any(|p| [p.capture.pursuer_arc, p.capture.evader_arc].iter().any(|x| *x < 2e-3 || *x > std::f64::consts::TAU - 2e-3));
        if near { return Ok(()); }
        let (Some(want), Some(got)) = (ra.solution.upper, rb.solution.upper) else { return Ok(()) };
        let got = b.units.seconds(got);
        let rel = (got - want).abs() / want.abs().max(1.0);
        if rel > 5e-4 {
            let m = |r: &twocars::GameReport<f64>| r.pairs.map(|row| row.map(|p| p.map(|p| (p.capture.value, p.capture.pursuer_arc, p.capture.evader_arc, p.tangent.length, p.capture.overshoot))));
            let mb = rb.pairs.map(|row| row.map(|p| p.map(|p| (b.units.seconds(p.capture.value), p.capture.pursuer_arc.to_f64(), p.capture.evader_arc.to_f64(), b.units.length(p.tangent.length), p.capture.overshoot))));
            cell.borrow_mut().push((rel, format!("{o:?}\n units {:?}\n f64 {:?} {:?}\n fix {:?} {:?}\n f64 pairs {:?}\n fix pairs {:?}", b.units, ra.solution.row, ra.solution.col, rb.solution.row, rb.solution.col, m(&ra), mb)));
        }
        Ok(())
    }).unwrap();
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (r, s) in worst.iter().take(3) {
        println!("rel {r:.2e}\n{s}\n");
    }
}
