//! MOVE TO / MOVE FOR on a DSP axis: a trapezoid from rest, queued as velocity ramps.

use super::Orion;
use crate::devices::orion::dsp::Queued;

impl Orion {
    /// `MOVE axis TO position` / `MOVE axis FOR distance` [`AT` speed RPM] [`IN` time ms]: a
    /// trapezoid from rest, queued as its velocity ramps (accelerate, cruise, decelerate).
    pub(super) fn move_to(
        &mut self,
        n: u32,
        relative: bool,
        target: f64,
        speed_rpm: Option<f64>,
        time_ms: Option<f64>,
    ) -> Result<Queued, String> {
        let i = self
            .configs
            .iter()
            .position(|c| c.number == n)
            .ok_or_else(|| format!("axis {n} is not defined in machine.toml"))?;
        let (config, defaults) = (&self.configs[i], self.defaults[i]);
        if self.dsp.queued(n).map_err(|e| e.0)? > 0 || self.dsp.velocity(n).map_err(|e| e.0)? != 0.0
        {
            return Err(format!(
                "MOVE TO/FOR on axis {n} starts from rest: the axis is moving or has moves \
                 queued (wait until DSP.DONE@ and stop it with MOVE … AT 0)"
            ));
        }
        if config.queue_depth < 3 {
            return Err(format!(
                "MOVE TO/FOR on axis {n} needs 3 places in its motion queue (queue = {})",
                config.queue_depth
            ));
        }
        let here = self.dsp.position(n).map_err(|e| e.0)?;
        let distance = if relative { target } else { target - here };
        let per_rpm = config.units_per_rev / 60.0;
        let finite = |x: f64, what: &str| {
            if x.is_finite() {
                Ok(x)
            } else {
                Err(format!(
                    "MOVE on axis {n}: the {what} must be a number, not {x}"
                ))
            }
        };
        finite(distance, "position")?;
        if distance == 0.0 {
            return Ok(Queued::Accepted);
        }
        let speed = finite(speed_rpm.unwrap_or(defaults.speed_rpm), "speed")?.abs() * per_rpm;
        if speed == 0.0 && time_ms.is_none() {
            return Err(format!(
                "MOVE TO/FOR on axis {n}: at 0 RPM the axis never arrives; give a speed above 0 (AT)"
            ));
        }
        // Times of the accelerating and cruising parts, and the top speed.
        let (ta, tc, v) = match time_ms {
            None => {
                let a = defaults.accel;
                let ta = speed / a;
                if speed * ta >= distance.abs() {
                    // A triangle: the speed is never reached.
                    let ta = (distance.abs() / a).sqrt();
                    (ta, 0.0, a * ta)
                } else {
                    (ta, distance.abs() / speed - ta, speed)
                }
            }
            Some(ms) => {
                let total = finite(ms, "time")? / 1000.0;
                if total <= 0.0 {
                    return Err(format!("MOVE on axis {n}: IN needs a time above 0 ms"));
                }
                match speed_rpm {
                    // Thirds: accelerate, cruise, decelerate.
                    None => (total / 3.0, total / 3.0, 1.5 * distance.abs() / total),
                    Some(_) => {
                        let ta = total - distance.abs() / speed;
                        if !(ta > 0.0 && ta <= total / 2.0) {
                            return Err(format!(
                                "MOVE on axis {n}: {distance} units at {} RPM cannot take {ms} ms",
                                speed / per_rpm
                            ));
                        }
                        (ta, total - 2.0 * ta, speed)
                    }
                }
            }
        };
        // A move so long at so low a speed that its times overflow: no run could see it end.
        if !(ta.is_finite() && tc.is_finite() && v.is_finite()) {
            return Err(format!(
                "MOVE on axis {n}: {} units at {} RPM would never end",
                crate::diag::number(distance.abs()),
                crate::diag::number(speed / per_rpm)
            ));
        }
        let rpm = v.copysign(distance) / per_rpm;
        let mut ramps = vec![(rpm, ta)];
        if tc > 0.0 {
            ramps.push((rpm, tc));
        }
        ramps.push((0.0, ta));
        for (r, t) in ramps {
            if self.dsp.move_at(n, r, t * 1000.0).map_err(|e| e.0)? == Queued::Full {
                return Err(format!("MOVE on axis {n}: the motion queue is full"));
            }
        }
        Ok(Queued::Accepted)
    }
}
