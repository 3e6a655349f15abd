//! Belts and the workpieces tracked on them: each workpiece is a product coordinate system
//! (PCS) that moves with its belt's travel from the instant the detector reported it.

use super::frame::Frame;

/// Most workpieces one belt tracks (the manual's limit; one more is warning 17918).
pub const MAX_WORKPIECES: usize = 30;

/// A workpiece on a belt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Workpiece {
    /// Stream id (from the scenario, or a count of receive edges).
    pub id: u32,
    /// Belt travel at the receive edge.
    pub travel0: f64,
    /// Position in belt coordinates at the receive edge (X, Y, Z, A, B, C); known once
    /// xValidPos has risen.
    pub pos0: Option<[f64; 6]>,
}

impl Workpiece {
    /// Its X on the belt (along the belt's travel) when the belt has travelled `travel`.
    pub fn belt_x(&self, travel: f64) -> Option<f64> {
        self.pos0.map(|p| p[0] + travel - self.travel0)
    }
}

/// One conveying belt as the module sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct Belt {
    /// Belt number (1–16).
    pub number: u32,
    /// Travel now, mm.
    pub travel: f64,
    /// Speed now, mm/s.
    pub velocity: f64,
    /// Its coordinate system in the machine's (alrConveyorBeltOrigin).
    pub frame: Frame,
    /// The alrConveyorBeltOrigin the frame was made from.
    pub origin: [f64; 6],
    /// Tracked workpieces, oldest (furthest downstream) first.
    pub pieces: Vec<Workpiece>,
    /// Workpieces taken from (or placed on) this belt.
    pub picked: u32,
    /// Workpieces dropped: left the operating range before they could be taken.
    pub missed: u32,
}

impl Belt {
    /// A belt with no workpieces.
    pub fn new(number: u32) -> Belt {
        Belt {
            number,
            travel: 0.0,
            velocity: 0.0,
            frame: Frame::IDENTITY,
            origin: [0.0; 6],
            pieces: Vec::with_capacity(MAX_WORKPIECES),
            picked: 0,
            missed: 0,
        }
    }

    /// A receive edge at belt travel `travel0`: start tracking a workpiece whose position is not
    /// known yet. `false` when the list is full (warning 17918).
    pub fn receive(&mut self, id: u32, travel0: f64) -> bool {
        if self.pieces.len() >= MAX_WORKPIECES {
            return false;
        }
        self.pieces.push(Workpiece {
            id,
            travel0,
            pos0: None,
        });
        true
    }

    /// A valid-position edge: the oldest workpiece still without a position gets `pos`.
    /// `false` when none is waiting.
    pub fn validate(&mut self, pos: [f64; 6]) -> bool {
        match self.pieces.iter_mut().find(|w| w.pos0.is_none()) {
            Some(w) => {
                w.pos0 = Some(pos);
                true
            }
            None => false,
        }
    }

    /// Where a workpiece is in the machine's coordinates when the belt has travelled `travel`.
    pub fn position_of(&self, w: &Workpiece, travel: f64) -> Option<[f64; 3]> {
        let p = w.pos0?;
        Some(self.frame.apply([p[0] + travel - w.travel0, p[1], p[2]]))
    }

    /// The workpiece's C in the machine (its C on the belt plus the belt's).
    pub fn c_of(&self, w: &Workpiece) -> f64 {
        w.pos0.map_or(0.0, |p| p[5]) + self.frame.c_degrees()
    }

    /// The belt's direction of travel in the machine's coordinates.
    pub fn direction(&self) -> [f64; 3] {
        self.frame.x_axis()
    }

    /// The oldest workpiece, other than `skip`, whose X on the belt is beyond `limit` once the
    /// belt has carried it `carry` further: its id. The module asks this of every belt at every
    /// cycle, so the loop over the workpieces holds nothing else (travel and carry are given,
    /// not reloaded and recomputed for each workpiece).
    pub fn first_beyond(&self, skip: Option<u32>, carry: f64, limit: f64) -> Option<u32> {
        let travel = self.travel;
        self.pieces
            .iter()
            .filter(|w| Some(w.id) != skip)
            .find(|w| w.belt_x(travel).is_some_and(|x| x + carry > limit))
            .map(|w| w.id)
    }

    /// Remove the workpiece with `id`, if tracked.
    pub fn remove(&mut self, id: u32) -> Option<Workpiece> {
        let i = self.pieces.iter().position(|w| w.id == id)?;
        Some(self.pieces.remove(i))
    }
}
