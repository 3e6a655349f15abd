//! The Queue object: entries, offset and exit position, status bits.

use crate::registry::catalog::QUEUE_TYPE;
use crate::registry::Registry;
use crate::trace::{Event, EventKind, Trace};
use std::collections::VecDeque;

crate::bind_slots! {
    /// Slots of one queue's members.
    struct Slots for QUEUE_TYPE {
        data_out: "DataOut",
        offset: "QueueOffset",
        exit_position: "ExitPosition",
        exit: "QueueExit",
        compare_enable: "QueueCompareEnable",
        empty: "QueueEmpty",
        full: "QueueFull",
        overflow: "QueueOverflow",
        count: "QueueCount",
        full_level: "FullLevel",
    }
}

/// One queue.
#[derive(Debug, Clone)]
pub struct Queue {
    index: u32,
    entries: VecDeque<f64>,
    size: usize,
    s: Slots,
}

impl Queue {
    /// Queue `index` of the registry, holding at most `size` entries.
    pub fn new(registry: &Registry, index: u32, size: usize) -> Queue {
        Queue {
            index,
            entries: VecDeque::with_capacity(size),
            size,
            s: Slots::of(registry, index),
        }
    }

    /// `DataIn = value`: store the value, or set QueueOverflow when full.
    pub fn data_in(&mut self, value: f64, v: &mut [f64], trace: &mut Trace, tick: u64) {
        if self.entries.len() >= self.size {
            v[self.s.overflow as usize] = 1.0;
        } else {
            self.entries.push_back(value);
            if trace.enabled() {
                let exit = value + v[self.s.offset as usize];
                trace.emit(
                    tick,
                    &Event::QueueIn {
                        object: format!("Queue.{}", self.index).into(),
                        value,
                        exit,
                    },
                );
            } else {
                trace.count(EventKind::QueueIn);
            }
        }
        self.refresh(v);
    }

    /// `QueueRemove`: drop the oldest entry and clear QueueExit.
    pub fn remove(&mut self, v: &mut [f64]) {
        self.entries.pop_front();
        v[self.s.exit as usize] = 0.0;
        self.refresh(v);
    }

    /// `QueueClear`: empty the queue and clear its status.
    pub fn clear(&mut self, v: &mut [f64]) {
        self.entries.clear();
        v[self.s.exit as usize] = 0.0;
        v[self.s.overflow as usize] = 0.0;
        self.refresh(v);
    }

    /// Whether it holds no entry.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// QueueExit turns on when the compare is enabled, the queue holds an entry, and the source
    /// is at or past the oldest entry's exit position; it stays on until QueueRemove.
    pub fn compare(&mut self, source: f64, v: &mut [f64], trace: &mut Trace, tick: u64) {
        if v[self.s.compare_enable as usize] == 0.0 || v[self.s.exit as usize] != 0.0 {
            return;
        }
        let Some(front) = self.entries.front() else {
            return;
        };
        let exit = front + v[self.s.offset as usize];
        if source >= exit {
            v[self.s.exit as usize] = 1.0;
            trace.emit(
                tick,
                &Event::QueueExit {
                    object: format!("Queue.{}", self.index).into(),
                    exit,
                },
            );
        }
    }

    /// Recompute the derived members after any change (entries, offset, full level).
    pub fn refresh(&self, v: &mut [f64]) {
        let n = self.entries.len();
        let front = self.entries.front().copied();
        v[self.s.count as usize] = n as f64;
        v[self.s.empty as usize] = f64::from(n == 0);
        v[self.s.full as usize] = f64::from(n as f64 >= v[self.s.full_level as usize]);
        v[self.s.data_out as usize] = front.unwrap_or(0.0);
        v[self.s.exit_position as usize] = front.map_or(0.0, |d| d + v[self.s.offset as usize]);
    }
}
