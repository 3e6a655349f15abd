//! REGIST on the DSP axes: the adapter between the REGIST model (one per axis) and the ORION
//! DSP axes it runs on. Each update it gathers the fast-input edges (scenario marks and wired
//! inputs, at their exact times and positions), classifies them, re-references the axes at
//! good marks and releases the corrections to the geared axes; programs reach it through the
//! kernel functions (`REGIST`, `STATUSSV`, `READ_SV`, `WRITE_SV`).

use super::{MarkClass, Regist, RegistParams};
use crate::devices::command::KernelFunc;
use crate::devices::orion::dsp::{DspAxes, DspAxisConfig};
use crate::devices::Now;
use crate::registry::SlotId;
use crate::trace::{Event, Origin};
use crate::world::InputActivity;

/// Marks on an axis seen by its fast input (from the scenario).
#[derive(Debug, Clone)]
pub struct FastTrack {
    /// The axis the marks are printed on.
    pub axis: u32,
    /// Mark positions, ascending.
    pub positions: Vec<f64>,
    /// How long the sensor stays on at each mark, s.
    pub on_time: f64,
    /// Times the sensor turns off again, pending.
    falls: Vec<f64>,
}

impl FastTrack {
    /// Marks at `positions` on `axis`, each seen for `on_time` seconds.
    pub fn new(axis: u32, positions: Vec<f64>, on_time: f64) -> FastTrack {
        FastTrack {
            axis,
            positions,
            on_time,
            falls: Vec::new(),
        }
    }
}

/// REGIST on every DSP axis of a machine (indexes follow the axes' set-up order).
#[derive(Debug, Clone)]
pub struct RegistAxes {
    /// Each axis's number and the axis that paces it.
    configs: Vec<(u32, Option<u32>)>,
    /// Per axis: REGIST's servo side.
    regists: Vec<Regist>,
    /// Per axis: what is added to the axis's continuous position to report it (DIM
    /// re-referencing at good marks).
    reference: Vec<f64>,
    /// Per axis: the continuous position at the previous update.
    last: Vec<f64>,
    /// Fast-input marks.
    fast: Vec<FastTrack>,
    /// Inputs wired to axes' fast inputs: (axis index, input slot).
    fast_inputs: Vec<(usize, SlotId)>,
    /// Per axis: the numbers of the axes it paces (fixed by the machine file).
    followers: Vec<Vec<u32>>,
    /// Per axis, during an update: how far its window crossings have been looked for.
    cursor: Vec<f64>,
}

impl RegistAxes {
    /// REGIST on the axes `configs`, with the scenario's fast-input marks.
    pub fn new(
        configs: &[DspAxisConfig],
        fast: Vec<FastTrack>,
        servo_update: f64,
    ) -> Result<RegistAxes, String> {
        let followers = configs
            .iter()
            .map(|m| {
                configs
                    .iter()
                    .filter(|f| f.pacer == Some(m.number))
                    .map(|f| f.number)
                    .collect()
            })
            .collect();
        let regists = configs
            .iter()
            .map(|_| Regist::new(servo_update).map_err(|e| e.0))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(RegistAxes {
            configs: configs.iter().map(|c| (c.number, c.pacer)).collect(),
            reference: vec![0.0; regists.len()],
            cursor: vec![0.0; regists.len()],
            last: vec![0.0; regists.len()],
            regists,
            fast,
            fast_inputs: Vec::new(),
            followers,
        })
    }

    /// Wire input `slot` to the fast input of axis `n` (its edges keep their exact times).
    pub fn wire_fast_input(&mut self, n: u32, slot: SlotId) -> Result<(), String> {
        let i = self
            .configs
            .iter()
            .position(|c| c.0 == n)
            .ok_or_else(|| format!("axis {n} is not a DSP axis of this machine"))?;
        self.fast_inputs.push((i, slot));
        Ok(())
    }

    /// What is added to axis `i`'s continuous position to report it.
    pub fn reference(&self, i: usize) -> f64 {
        self.reference.get(i).copied().unwrap_or(0.0)
    }

    /// Axis `i` stands at continuous position `p` at the end of this update.
    pub fn note_position(&mut self, i: usize, p: f64) {
        if let Some(l) = self.last.get_mut(i) {
            *l = p;
        }
    }

    /// A kernel function on the DSP axes (`REGIST`, `STATUSSV`, `READ_SV`, `WRITE_SV`).
    pub fn call(
        &mut self,
        func: KernelFunc,
        args: &[f64],
        now: &mut Now<'_>,
    ) -> Result<f64, String> {
        let arg = |i: usize| args.get(i).copied().unwrap_or(0.0);
        let axis = arg(if func == KernelFunc::Regist { 1 } else { 0 });
        let Some(i) = self.index_of(axis) else {
            return Err(not_dsp_axis(axis));
        };
        match func {
            KernelFunc::StatusSv => Ok(f64::from(self.regists[i].status())),
            KernelFunc::ReadSv => self.regists[i]
                .read_sv(servo_variable(arg(1))?)
                .map_err(|e| e.0),
            KernelFunc::WriteSv => {
                let var = servo_variable(arg(1))?;
                self.regists[i].write_sv(var, arg(2)).map_err(|e| e.0)?;
                Ok(1.0)
            }
            KernelFunc::Regist => self.regist(i, axis as u32, args, now),
        }
    }

    /// The index of the DSP axis numbered `axis` (a kernel function's argument, so any number).
    #[inline]
    fn index_of(&self, axis: f64) -> Option<usize> {
        self.configs.iter().position(|c| f64::from(c.0) == axis)
    }

    /// The value of a polled function (`STATUSSV`, `READ_SV`) whose arguments are right;
    /// `None` for anything else, which [`RegistAxes::call`] does or refuses.
    #[inline]
    pub fn poll(&self, func: KernelFunc, args: &[f64]) -> Option<f64> {
        // Only the reads: `REGIST`'s first argument is not even an axis.
        if !matches!(func, KernelFunc::StatusSv | KernelFunc::ReadSv) {
            return None;
        }
        let regist = self.regists.get(self.index_of(*args.first()?)?)?;
        if func == KernelFunc::StatusSv {
            return Some(f64::from(regist.status()));
        }
        regist.read_sv(servo_variable(*args.get(1)?).ok()?).ok()
    }

    /// `REGIST(EN, AXIS, DIST, TOLR, IGNR, LGTH, DIM)` on the axis of index `i` (number `n`):
    /// apart from the polled functions, which a registration loop calls every scan, so the
    /// polled ones stay small enough to inline.
    #[inline(never)]
    fn regist(&mut self, i: usize, n: u32, args: &[f64], now: &mut Now<'_>) -> Result<f64, String> {
        let arg = |i: usize| args.get(i).copied().unwrap_or(0.0);
        let regist = &mut self.regists[i];
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
        let ok = regist.ok();
        // A mark is an edge the axis makes crossing it: one under the axis now is
        // never seen, which the examples avoid by backing the axis off first.
        let here = self.last[i];
        let tol = 1e-9 * here.abs().max(1.0);
        let under = self
            .fast
            .iter()
            .filter(|track| track.axis == n)
            .any(|track| track.positions.iter().any(|&m| (m - here).abs() <= tol));
        if ok && under {
            now.trace.emit(
                now.tick,
                &Event::Warning {
                    origin: Origin::Axis { axis: n },
                    message: format!(
                        "REGIST enabled with axis {n} standing on a mark (position \
                         {here}): that mark is never seen, since a mark is seen when the \
                         axis crosses it; back the axis off the mark before enabling"
                    )
                    .into(),
                },
            );
        }
        Ok(f64::from(ok))
    }

    /// Fast-input edges of this update, in time order: (time, rising, axis index, position).
    fn fast_edges(
        &mut self,
        dsp: &DspAxes,
        t: f64,
        activity: &[InputActivity],
    ) -> Result<Vec<(f64, bool, usize, f64)>, String> {
        let t0 = dsp.previous_time();
        let mut edges = Vec::new();
        for &(i, slot) in &self.fast_inputs {
            let n = self.configs[i].0;
            let Some(a) = activity.iter().find(|a| a.slot == slot) else {
                continue;
            };
            for (at, rising) in [(a.first_rise, true), (a.first_fall, false)] {
                if let Some(at) = at {
                    let at = at.clamp(t0, t);
                    let p = dsp.position_at(n, at).map_err(|e| e.0)?;
                    edges.push((at, rising, i, p));
                }
            }
        }
        for track in &mut self.fast {
            let Some(i) = self.configs.iter().position(|c| c.0 == track.axis) else {
                continue;
            };
            let n = track.axis;
            let (p0, p1) = (self.last[i], dsp.position(n).map_err(|e| e.0)?);
            // A mark belongs to the update whose end position reaches it: (p0, p1] going
            // forward, [p1, p0) going back. A mark a rounding error past the end position is
            // at the update's end (the positions of two updates are computed separately).
            let tol = |x: f64| 1e-9 * x.abs().max(1.0);
            let (from, to) = if p1 >= p0 {
                (
                    track.positions.partition_point(|&m| m <= p0 + tol(p0)),
                    track.positions.partition_point(|&m| m <= p1 + tol(p1)),
                )
            } else {
                (
                    track.positions.partition_point(|&m| m < p1 - tol(p1)),
                    track.positions.partition_point(|&m| m < p0 - tol(p0)),
                )
            };
            for &m in &track.positions[from..to.max(from)] {
                let at = dsp
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
                    let p = dsp.position_at(n, f).map_err(|e| e.0)?;
                    edges.push((f, false, i, p));
                } else {
                    k += 1;
                }
            }
        }
        edges.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)));
        Ok(edges)
    }

    /// REGIST's servo side for this update: fast-input marks classified, window crossings, DIM
    /// re-referencing, all at their exact times and in time order across the axes (a mark and
    /// a crossing at the same instant: the mark first, since the window closes only when the
    /// axis goes past its end without one); then corrections released to the axes.
    pub fn update(
        &mut self,
        dsp: &mut DspAxes,
        t: f64,
        activity: &[InputActivity],
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        let t0 = dsp.previous_time();
        self.cursor.fill(t0);
        for (time, rising, i, position) in self.fast_edges(dsp, t, activity)? {
            self.windows_until(dsp, time, false, now)?;
            self.take_edge(i, time, rising, position, now)?;
            self.cursor[i] = self.cursor[i].max(time);
        }
        self.windows_until(dsp, t, true, now)?;
        for (i, &(n, pacer)) in self.configs.iter().enumerate() {
            let ratio = dsp.ratio(n).map_err(|e| e.0)?;
            let (master_moving, ratio_move) = match (pacer, ratio) {
                // Slave registration: this axis runs the ratio move.
                (Some(p), Some(_)) => (dsp.velocity(p).map_err(|e| e.0)? != 0.0, true),
                // Master registration: this axis is the master of the ratio moves.
                _ => {
                    let mut geared = false;
                    for &f in &self.followers[i] {
                        geared |= dsp.ratio(f).map_err(|e| e.0)?.is_some();
                    }
                    (dsp.velocity(n).map_err(|e| e.0)? != 0.0, geared)
                }
            };
            let (slave, master) = self.regists[i].take_correction(master_moving, ratio_move);
            match ratio {
                Some(r) => {
                    // A master offset moves the position the slave's gear follows: r × it.
                    let delta = slave + r * master;
                    if delta != 0.0 {
                        dsp.shift(n, delta).map_err(|e| e.0)?;
                    }
                }
                // No slave of its own (a slave correction has nothing to move): the master
                // correction moves every axis geared to this one by its ratio.
                None if master != 0.0 => {
                    for &f in &self.followers[i] {
                        if let Some(r) = dsp.ratio(f).map_err(|e| e.0)? {
                            dsp.shift(f, r * master).map_err(|e| e.0)?;
                        }
                    }
                }
                None => {}
            }
        }
        Ok(())
    }

    /// One fast-input edge of axis index `i`: classified, traced, the axis re-referenced at a
    /// good mark; a rising edge inside the minimum time is not seen, and the trace says so.
    fn take_edge(
        &mut self,
        i: usize,
        time: f64,
        rising: bool,
        position: f64,
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        let n = self.configs[i].0;
        let before = self.regists[i].status();
        if rising {
            if let Some(gap) = self.regists[i].too_soon(time) {
                let message = format!(
                    "REGIST: a mark at t = {time} s (position {position}) came {} ms after the \
                     last one, under the minimum time between marks of {} ms (servo variable \
                     25): it was not seen",
                    gap * 1e3,
                    self.regists[i].min_time() * 1e3
                );
                now.trace.emit(
                    now.tick,
                    &Event::Warning {
                        origin: Origin::Axis { axis: n },
                        message: message.into(),
                    },
                );
            }
        }
        if let Some(mark) = self.regists[i]
            .edge(time, position, rising)
            .map_err(|e| e.0)?
        {
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
        self.status_event(i, before, time, now);
        Ok(())
    }

    /// Every DIST + TOLR crossing of any axis from its cursor up to `until` (`inclusive`: at
    /// `until` too), in time order: each is traced at its exact time with the threshold.
    fn windows_until(
        &mut self,
        dsp: &DspAxes,
        until: f64,
        inclusive: bool,
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        loop {
            let mut first: Option<(f64, usize, f64)> = None;
            for (i, regist) in self.regists.iter().enumerate() {
                let Some(threshold) = regist.window_threshold() else {
                    continue;
                };
                let (n, from) = (self.configs[i].0, self.cursor[i]);
                if from > until {
                    continue;
                }
                let crossing = if dsp.position_at(n, from).map_err(|e| e.0)? >= threshold {
                    Some(from)
                } else {
                    dsp.time_at_position(n, threshold, from, until)
                        .map_err(|e| e.0)?
                };
                let Some(tc) = crossing.filter(|&tc| inclusive || tc < until) else {
                    continue;
                };
                if first.is_none_or(|(best, _, _)| tc < best) {
                    first = Some((tc, i, threshold));
                }
            }
            let Some((tc, i, threshold)) = first else {
                return Ok(());
            };
            let before = self.regists[i].status();
            self.regists[i].pass_window();
            self.cursor[i] = tc;
            now.trace.emit(
                now.tick,
                &Event::RegistWindow {
                    axis: self.configs[i].0,
                    time: tc,
                    position: threshold,
                },
            );
            self.status_event(i, before, tc, now);
        }
    }

    /// A `regist_status` event when axis index `i`'s STATUSSV is no longer `before`.
    fn status_event(&self, i: usize, before: u32, time: f64, now: &mut Now<'_>) {
        let status = self.regists[i].status();
        if status != before {
            now.trace.emit(
                now.tick,
                &Event::RegistStatus {
                    axis: self.configs[i].0,
                    time,
                    status,
                },
            );
        }
    }
}

/// The fault of a kernel function given an axis that is not a DSP axis: away from the polled
/// reads, which a registration loop makes every scan.
#[cold]
fn not_dsp_axis(axis: f64) -> String {
    format!("axis {axis} is not a DSP axis of this machine ([axis.N])")
}

/// A servo variable number of `READ_SV`/`WRITE_SV`: a whole number from 0 to 1000.
fn servo_variable(x: f64) -> Result<u32, String> {
    if x.fract() == 0.0 && (0.0..=1000.0).contains(&x) {
        Ok(x as u32)
    } else {
        Err(format!("{x} is not a servo variable number"))
    }
}
