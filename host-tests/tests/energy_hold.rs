//! The unit's energy hold (`twocars::mavlink::energy`) flying a point-mass aircraft: lift
//! proportional to v^2 and the angle of attack, drag to v^2, thrust to the throttle, and a
//! pitch that follows its setpoint with a 0.3 s lag. Trimmed at 10 m/s with 0.05 rad of
//! attack and 0.6 throttle, and started off trim; banks of 40 degrees either way ask for more
//! lift and thrust than level flight.

use twocars::mavlink::energy::{EnergyHold, Flight};

const G: f64 = 9.80665;
/// Lift per v^2 per rad of attack: g at 10 m/s and 0.05 rad.
const LIFT: f64 = G / (100.0 * 0.05);
/// Full throttle's acceleration, m/s^2, and drag per v^2: 0.6 throttle balances at 10 m/s.
const THRUST: f64 = 5.0;
const DRAG: f64 = 0.6 * THRUST / 100.0;

struct Aircraft {
    height: f64,
    speed: f64,
    path: f64,
    pitch: f64,
}

impl Aircraft {
    /// Advances `dt` under pitch setpoint `pitch` (rad), `throttle` and `bank` (rad).
    fn step(&mut self, pitch: f64, throttle: f64, bank: f64, dt: f64) {
        self.pitch += (pitch - self.pitch) * dt / 0.3;
        let attack = self.pitch - self.path;
        let lift = LIFT * self.speed * self.speed * attack;
        self.path += dt * (lift * bank.cos() - G * self.path.cos()) / self.speed;
        self.speed +=
            dt * (THRUST * throttle - DRAG * self.speed * self.speed - G * self.path.sin());
        self.height += dt * self.speed * self.path.sin();
    }
}

/// The worst height error (m) and airspeed error (m/s) from 8 s on, flying `banks` (rad,
/// 20 s each) from 100 m (the height the hold takes) at `v0` m/s on a flight path `path` (rad).
fn fly(banks: &[f64], v0: f64, path: f64) -> (f64, f64) {
    let mut hold = EnergyHold::new();
    let mut plane = Aircraft {
        height: 100.0,
        speed: v0,
        path,
        pitch: 0.0,
    };
    let (dt, control) = (0.005, 10);
    let (mut worst_height, mut worst_speed) = (0.0f64, 0.0f64);
    let mut command = (0.0, 0.5);
    for (k, &bank) in banks.iter().enumerate() {
        for i in 0..4000 {
            if i % control == 0 {
                let flight = Flight {
                    height: plane.height as f32,
                    climb: (plane.speed * plane.path.sin()) as f32,
                    airspeed: plane.speed as f32,
                };
                let e = hold.command(flight, 10.0, (dt * control as f64) as f32);
                command = (f64::from(e.pitch), f64::from(e.throttle));
            }
            plane.step(command.0, command.1, bank, dt);
            let t = k as f64 * 20.0 + i as f64 * dt;
            assert!(
                plane.height.is_finite() && plane.speed > 3.0,
                "lost at {t} s"
            );
            if t >= 8.0 {
                worst_height = worst_height.max((plane.height - 100.0).abs());
                worst_speed = worst_speed.max((plane.speed - 10.0).abs());
            }
        }
    }
    (worst_height, worst_speed)
}

#[test]
fn it_holds_height_and_airspeed_through_banks_either_way() {
    let banks = [0.0, 40f64.to_radians(), -40f64.to_radians(), 0.0];
    let (height, speed) = fly(&banks, 12.0, -0.1);
    assert!(
        height < 3.0 && speed < 0.6,
        "height {height} m, speed {speed} m/s"
    );
}

#[test]
fn the_height_held_is_the_one_it_starts_at_and_reset_forgets_it() {
    let mut hold = EnergyHold::new();
    let level = |height| Flight {
        height,
        climb: 0.0,
        airspeed: 10.0,
    };
    assert_eq!(hold.height(), None);
    hold.command(level(50.0), 10.0, 0.05);
    hold.command(level(40.0), 10.0, 0.05);
    assert_eq!(hold.height(), Some(50.0));
    hold.reset();
    hold.command(level(40.0), 10.0, 0.05);
    assert_eq!(hold.height(), Some(40.0));
}

#[test]
fn non_finite_input_gives_level_pitch_and_keeps_the_memory() {
    let mut hold = EnergyHold::new();
    let flight = Flight {
        height: 50.0,
        climb: 0.0,
        airspeed: 8.0,
    };
    let first = hold.command(flight, 10.0, 0.05);
    let before = hold;
    for bad in [
        Flight {
            height: f32::NAN,
            ..flight
        },
        Flight {
            airspeed: f32::INFINITY,
            ..flight
        },
    ] {
        let e = hold.command(bad, 10.0, 0.05);
        assert_eq!(e.pitch, 0.0);
        assert!((0.0..=1.0).contains(&e.throttle));
        assert_eq!(hold, before);
    }
    assert_eq!(hold.command(flight, f32::NAN, 0.05).pitch, 0.0);
    assert!(first.throttle > 0.5, "slow: more than the starting trim");
}

/// Level at the reference airspeed: the first command's throttle is the trim the hold starts
/// from, plus nothing.
fn first_throttle(hold: &mut EnergyHold) -> f32 {
    let on_trim = Flight {
        height: 50.0,
        climb: 0.0,
        airspeed: 10.0,
    };
    hold.command(on_trim, 10.0, 0.05).throttle
}

#[test]
fn taking_over_it_starts_from_the_autopilots_throttle_until_it_has_flown() {
    let mut fresh = EnergyHold::new();
    assert!((first_throttle(&mut fresh) - 0.5).abs() < 1e-6);
    let mut seeded = EnergyHold::new();
    seeded.seed_throttle(0.8);
    assert!((first_throttle(&mut seeded) - 0.8).abs() < 1e-6);
    // Once it has flown, the trim it learnt stays: a later seed moves nothing.
    let before = seeded;
    seeded.seed_throttle(0.1);
    assert_eq!(seeded, before);
    // Out of 0 to 1, or not a number: ignored.
    let mut odd = EnergyHold::new();
    for bad in [f32::NAN, -0.1, 1.5, f32::INFINITY] {
        odd.seed_throttle(bad);
    }
    assert!((first_throttle(&mut odd) - 0.5).abs() < 1e-6);
}

#[test]
fn a_seeded_takeover_of_the_trimmed_aircraft_loses_less_airspeed() {
    // The point mass on trim at 10 m/s needs 0.6 throttle; the fresh hold starts at 0.5.
    let worst = |seed: Option<f32>| {
        let mut hold = EnergyHold::new();
        if let Some(t) = seed {
            hold.seed_throttle(t);
        }
        let mut plane = Aircraft {
            height: 100.0,
            speed: 10.0,
            path: 0.0,
            pitch: 0.05,
        };
        let mut worst = 0.0f64;
        let mut command = (0.0, 0.0);
        for i in 0..1600 {
            if i % 10 == 0 {
                let flight = Flight {
                    height: plane.height as f32,
                    climb: (plane.speed * plane.path.sin()) as f32,
                    airspeed: plane.speed as f32,
                };
                let e = hold.command(flight, 10.0, 0.05);
                command = (f64::from(e.pitch), f64::from(e.throttle));
            }
            plane.step(command.0, command.1, 0.0, 0.005);
            worst = worst.max((plane.speed - 10.0).abs());
        }
        worst
    };
    // What is left seeded is the pitch trim's, which starts level while the aircraft flies
    // 0.05 rad nose up: 0.10 m/s at worst, against 0.17 m/s fresh.
    let (fresh, seeded) = (worst(None), worst(Some(0.6)));
    assert!(seeded < fresh, "seeded {seeded} m/s, fresh {fresh} m/s");
}
