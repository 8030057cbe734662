//! The order of the four motor outputs in `HIL_ACTUATOR_CONTROLS.controls[0..4]`: the
//! vehicle file's (the mixer's) order, or the order a simulator written for PX4 or Betaflight
//! assumes, found from the rotor positions.
//!
//! Quad X orders (body FLU: x forward, y left), output slots 1 to 4:
//! - PX4 (`Quadrotor x` geometry, e.g. the x500): front-right, rear-left, front-left,
//!   rear-right (PX4 airframe reference, "Quadrotor x");
//! - Betaflight (`QUADX`): rear-right, front-right, rear-left, front-left (Betaflight's
//!   motor-order diagram for QUADX).
//!
//! Spin directions are the vehicle file's: an order only places the outputs, it does not
//! reverse a propeller.

use crate::airframe::Rotor;

/// Which order the four motor outputs go in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotorOrder {
    /// The vehicle file's (the mixer's) order.
    Mixer,
    /// PX4's quad X order.
    Px4,
    /// Betaflight's QUADX order.
    Betaflight,
}

/// A rotor's quadrant, from its hub position.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Quadrant {
    FrontRight,
    RearLeft,
    FrontLeft,
    RearRight,
}

/// Why the rotors cannot be put in a quad X order: a quadrant with no rotor, or two (for
/// instance a plus-shaped frame, with its rotors on the axes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NotAQuadX;

fn quadrant(r: &Rotor) -> Option<Quadrant> {
    let [x, y] = r.position;
    match (x > 0.0, x < 0.0, y > 0.0, y < 0.0) {
        (true, _, _, true) => Some(Quadrant::FrontRight),
        (_, true, true, _) => Some(Quadrant::RearLeft),
        (true, _, true, _) => Some(Quadrant::FrontLeft),
        (_, true, _, true) => Some(Quadrant::RearRight),
        _ => None,
    }
}

impl MotorOrder {
    /// From a build setting: `mixer`, `px4` or `betaflight`.
    pub const fn parse(s: &str) -> Option<Self> {
        match s.as_bytes() {
            b"mixer" => Some(Self::Mixer),
            b"px4" => Some(Self::Px4),
            b"betaflight" => Some(Self::Betaflight),
            _ => None,
        }
    }

    /// `slots[k]`: the rotor (vehicle-file index) whose throttle goes to output `k`. Error:
    /// the rotors are not one per quadrant ([`NotAQuadX`]; never for [`MotorOrder::Mixer`]).
    pub fn slots(self, rotors: &[Rotor; 4]) -> Result<[usize; 4], NotAQuadX> {
        use Quadrant::*;
        let wanted = match self {
            Self::Mixer => return Ok([0, 1, 2, 3]),
            Self::Px4 => [FrontRight, RearLeft, FrontLeft, RearRight],
            Self::Betaflight => [RearRight, FrontRight, RearLeft, FrontLeft],
        };
        let mut slots = [0; 4];
        for (slot, q) in slots.iter_mut().zip(wanted) {
            let mut found = None;
            for (i, r) in rotors.iter().enumerate() {
                if quadrant(r) == Some(q) {
                    if found.is_some() {
                        return Err(NotAQuadX);
                    }
                    found = Some(i);
                }
            }
            *slot = found.ok_or(NotAQuadX)?;
        }
        Ok(slots)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotor(x: f32, y: f32) -> Rotor {
        Rotor {
            position: [x, y],
            spin: 1.0,
        }
    }

    /// The x500's file is in PX4's order already; the Crazyflie's (front-left, front-right,
    /// rear-right, rear-left) maps to both orders by hand.
    #[test]
    fn orders_from_positions() {
        let x500 = [
            rotor(0.174, -0.174),
            rotor(-0.174, 0.174),
            rotor(0.174, 0.174),
            rotor(-0.174, -0.174),
        ];
        assert_eq!(MotorOrder::Px4.slots(&x500), Ok([0, 1, 2, 3]));
        assert_eq!(MotorOrder::Betaflight.slots(&x500), Ok([3, 0, 1, 2]));
        let cf = [
            rotor(0.03, 0.03),
            rotor(0.03, -0.03),
            rotor(-0.03, -0.03),
            rotor(-0.03, 0.03),
        ];
        assert_eq!(MotorOrder::Px4.slots(&cf), Ok([1, 3, 0, 2]));
        assert_eq!(MotorOrder::Betaflight.slots(&cf), Ok([2, 1, 3, 0]));
        assert_eq!(MotorOrder::Mixer.slots(&cf), Ok([0, 1, 2, 3]));
    }

    /// A plus frame (rotors on the axes) or two rotors in one quadrant has no quad X order.
    #[test]
    fn not_a_quad_x() {
        let plus = [
            rotor(0.2, 0.0),
            rotor(0.0, 0.2),
            rotor(-0.2, 0.0),
            rotor(0.0, -0.2),
        ];
        assert!(MotorOrder::Px4.slots(&plus).is_err());
        let twice = [
            rotor(0.2, 0.2),
            rotor(0.1, 0.1),
            rotor(-0.2, -0.2),
            rotor(0.2, -0.2),
        ];
        assert_eq!(MotorOrder::Betaflight.slots(&twice), Err(NotAQuadX));
        assert_eq!(MotorOrder::parse("px4"), Some(MotorOrder::Px4));
        assert_eq!(MotorOrder::parse("PX4"), None);
    }
}
