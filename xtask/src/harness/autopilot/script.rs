//! The script every SITL run follows, whatever the autopilot and vehicle: start the unit, the
//! autopilot and the router between them; make the vehicle ready; measure it and give the law
//! its limits; configure the unit; fly each start; say what was flown. [`Vehicle`] is what
//! each autopilot and vehicle fills in: its binary, its readiness, its measurement, its chases.

use super::chase::{Outcome, Start};
use super::harness::Harness;
use super::{configure_unit, report, set_unit_params};
use twocars_sim::sim::theorem_threshold;

/// What a vehicle's measurement gives the unit.
#[derive(Debug, Clone)]
pub struct Law {
    /// v_pm, w_pm, v_em, w_em (m/s, 1/m, m/s, 1/m).
    pub limits: [f64; 4],
    /// TC_PERIOD, s: the vehicle's response to a turn.
    pub period: f64,
    /// TC_CAPTURE, m.
    pub capture: f64,
    /// The vehicle's own parameters of the unit (TC_VEHICLE, TC_BANK_EFF), set before the law's.
    pub unit_params: Vec<(&'static str, f64)>,
    /// How the law's line ends: the parameters and where the period comes from.
    pub note: String,
}

/// One autopilot and vehicle in SITL, as the script asks of it.
pub trait Vehicle {
    /// Starts the unit, the autopilot's SITL and the router between them, keeping what must run
    /// until the vehicle is dropped; the harness on the router.
    fn start(&mut self) -> Result<Harness, String>;
    /// Makes the vehicle ready to be driven (a position, its mode, armed); what it took.
    fn ready(&mut self, h: &mut Harness) -> Result<String, String>;
    /// Measures the vehicle under the unit's kind of setpoints; the law it flies.
    fn measure(&mut self, h: &mut Harness) -> Result<Law, String>;
    /// What the run sets after the unit's law (the field's radio and wind).
    fn configure(&mut self, _h: &mut Harness, _law: &Law) -> Result<(), String> {
        Ok(())
    }
    /// The starts it flies.
    fn starts(&mut self, law: &Law) -> Vec<Start>;
    /// Flies the `i`-th chase from `start`; its outcome and what to say under its report.
    fn chase(
        &mut self,
        h: &mut Harness,
        i: usize,
        start: Start,
        law: &Law,
    ) -> Result<(Outcome, Vec<String>), String>;
}

/// Runs the script on `vehicle`: the harness (for what the run measured beside the chases),
/// the law it flew and each chase's outcome.
pub fn fly(vehicle: &mut impl Vehicle) -> Result<(Harness, Law, Vec<Outcome>), String> {
    let mut h = vehicle.start()?;
    println!("ready: {}", vehicle.ready(&mut h)?);
    let law = vehicle.measure(&mut h)?;
    let l = law.limits;
    println!(
        "the law: v_pm {} m/s, w_pm {} 1/m, v_em {} m/s, w_em {} 1/m; threshold {:.1} m; {}",
        l[0],
        l[1],
        l[2],
        l[3],
        theorem_threshold(l),
        law.note
    );
    set_unit_params(&mut h, &law.unit_params)?;
    configure_unit(&mut h, l, law.capture, law.period)?;
    vehicle.configure(&mut h, &law)?;
    let mut outcomes = Vec::new();
    for (i, start) in vehicle.starts(&law).into_iter().enumerate() {
        let (outcome, notes) = vehicle.chase(&mut h, i, start, &law)?;
        println!("{}", report(&outcome, l));
        for note in notes {
            println!("  {note}");
        }
        outcomes.push(outcome);
    }
    Ok((h, law, outcomes))
}
