//! REGIST on the DSP axes: the kernel functions, the fast-input edges of an update, and what a
//! mark does to the axes (re-referencing, corrections released to the geared axes).

use super::Orion;
use crate::devices::command::KernelFunc;
use crate::kernel::regist::{MarkClass, RegistParams};
use crate::kernel::Now;
use crate::trace::{Event, Origin};
use crate::world::InputActivity;

impl Orion {
    /// A kernel function on the DSP axes (`REGIST`, `STATUSSV`, `READ_SV`, `WRITE_SV`).
    pub fn call(
        &mut self,
        func: KernelFunc,
        args: &[f64],
        _v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<f64, String> {
        let arg = |i: usize| args.get(i).copied().unwrap_or(0.0);
        let axis = arg(if func == KernelFunc::Regist { 1 } else { 0 });
        let n = axis as u32;
        let i = self
            .configs
            .iter()
            .position(|c| f64::from(c.number) == axis)
            .ok_or_else(|| format!("axis {axis} is not a DSP axis of this machine ([axis.N])"))?;
        let var = || {
            let x = arg(1);
            if x.fract() == 0.0 && (0.0..=1000.0).contains(&x) {
                Ok(x as u32)
            } else {
                Err(format!("{x} is not a servo variable number"))
            }
        };
        let regist = &mut self.regists[i];
        match func {
            KernelFunc::Regist => {
                if arg(0) == 0.0 {
                    regist.disable();
                    return Ok(0.0);
                }
                let params = RegistParams {
                    dist: arg(2),
                    tolr: arg(3),
                    ignr: arg(4),
                    lgth: arg(5),
                    dim: arg(6),
                };
                // As on the controller, bad values leave OK false; the trace says why.
                if let Err(e) = regist.enable(params) {
                    now.trace.emit(
                        now.tick,
                        &Event::Warning {
                            origin: Origin::Axis { axis: n },
                            message: format!("REGIST: {}", e.0).into(),
                        },
                    );
                }
                Ok(f64::from(regist.ok()))
            }
            KernelFunc::StatusSv => Ok(f64::from(regist.status())),
            KernelFunc::ReadSv => regist.read_sv(var()?).map_err(|e| e.0),
            KernelFunc::WriteSv => {
                regist.write_sv(var()?, arg(2)).map_err(|e| e.0)?;
                Ok(1.0)
            }
        }
    }

    /// Fast-input edges of this update, in time order: (time, rising, axis index, position).
    fn fast_edges(
        &mut self,
        t: f64,
        activity: &[InputActivity],
    ) -> Result<Vec<(f64, bool, usize, f64)>, String> {
        let t0 = self.dsp.previous_time();
        let mut edges = Vec::new();
        for &(i, slot) in &self.fast_inputs {
            let n = self.configs[i].number;
            let Some(a) = activity.iter().find(|a| a.slot == slot) else {
                continue;
            };
            for (at, rising) in [(a.first_rise, true), (a.first_fall, false)] {
                if let Some(at) = at {
                    let at = at.clamp(t0, t);
                    let p = self.dsp.position_at(n, at).map_err(|e| e.0)?;
                    edges.push((at, rising, i, p));
                }
            }
        }
        for track in &mut self.fast {
            let Some(i) = self.configs.iter().position(|c| c.number == track.axis) else {
                continue;
            };
            let n = track.axis;
            let (p0, p1) = (self.last[i], self.dsp.position(n).map_err(|e| e.0)?);
            let (lo, hi) = (p0.min(p1), p0.max(p1));
            let from = track.positions.partition_point(|&m| m <= lo);
            let to = track.positions.partition_point(|&m| m <= hi);
            for &m in &track.positions[from..to] {
                let at = self
                    .dsp
                    .time_at_position(n, m, t0, t)
                    .map_err(|e| e.0)?
                    .unwrap_or(t);
                edges.push((at, true, i, m));
                track.falls.push(at + track.on_time);
            }
            // The sensor turning off in this update (the edges are sorted below).
            let mut k = 0;
            while k < track.falls.len() {
                if track.falls[k] <= t {
                    let f = track.falls.swap_remove(k).max(t0);
                    let p = self.dsp.position_at(n, f).map_err(|e| e.0)?;
                    edges.push((f, false, i, p));
                } else {
                    k += 1;
                }
            }
        }
        edges.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)));
        Ok(edges)
    }

    /// REGIST's servo side for this update: fast-input marks classified and traced, DIM
    /// re-referencing, the window event, and corrections released to the axis.
    pub(super) fn registration(
        &mut self,
        t: f64,
        activity: &[InputActivity],
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        for (time, rising, i, position) in self.fast_edges(t, activity)? {
            let n = self.configs[i].number;
            let Some(mark) = self.regists[i]
                .edge(time, position, rising)
                .map_err(|e| e.0)?
            else {
                continue;
            };
            let class = match mark.class {
                MarkClass::Good => "good",
                MarkClass::Bad => "bad",
                MarkClass::Ignored => "ignored",
            };
            now.trace.emit(
                now.tick,
                &Event::Regist {
                    axis: n,
                    mark: class.into(),
                    time,
                    position: mark.position,
                    correction: mark.correction,
                },
            );
            if let Some(dim) = mark.rereference {
                self.reference[i] = dim - mark.position;
            }
        }
        for (i, c) in self.configs.iter().enumerate() {
            let n = c.number;
            let p = self.dsp.position(n).map_err(|e| e.0)?;
            if self.regists[i].passed(p).map_err(|e| e.0)? {
                now.trace.emit(
                    now.tick,
                    &Event::RegistWindow {
                        axis: n,
                        position: p,
                    },
                );
            }
            let ratio = self.dsp.ratio(n).map_err(|e| e.0)?;
            let (master_moving, ratio_move) = match (c.pacer, ratio) {
                // Slave registration: this axis runs the ratio move.
                (Some(p), Some(_)) => (self.dsp.velocity(p).map_err(|e| e.0)? != 0.0, true),
                // Master registration: this axis is the master of the ratio moves.
                _ => {
                    let mut geared = false;
                    for &f in &self.followers[i] {
                        geared |= self.dsp.ratio(f).map_err(|e| e.0)?.is_some();
                    }
                    (self.dsp.velocity(n).map_err(|e| e.0)? != 0.0, geared)
                }
            };
            let (slave, master) = self.regists[i].take_correction(master_moving, ratio_move);
            match ratio {
                Some(r) => {
                    // A master offset moves the position the slave's gear follows: r × it.
                    let delta = slave + r * master;
                    if delta != 0.0 {
                        self.dsp.shift(n, delta).map_err(|e| e.0)?;
                    }
                }
                // No slave of its own (a slave correction has nothing to move): the master
                // correction moves every axis geared to this one by its ratio.
                None if master != 0.0 => {
                    for &f in &self.followers[i] {
                        if let Some(r) = self.dsp.ratio(f).map_err(|e| e.0)? {
                            self.dsp.shift(f, r * master).map_err(|e| e.0)?;
                        }
                    }
                }
                None => {}
            }
        }
        Ok(())
    }
}
