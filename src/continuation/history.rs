//! The accepted points a path keeps for its predictor.

use super::Accepted;

/// The last four accepted points of a path (one at its start), all the predictor needs.
///
/// A ring: accepting a point overwrites the oldest slot's storage, so a step moves one point
/// (the trial, swapped into the slot) where shifting four `Accepted` values down a line copied
/// each (3 % of a 3R fit's time was that copying).
#[derive(Debug, Clone)]
pub struct History<P> {
    /// Up to four points, in order of acceptance until full, then a ring (inline: a path
    /// allocates none for them).
    slots: [Option<Accepted<P>>; KEPT],
    /// How many are kept.
    len: usize,
    /// The slot of the last accepted point.
    head: usize,
}

/// How many accepted points a [`History`] keeps: four, for the cubic predictor
/// ([`Predictor::Cubic`](super::Predictor::Cubic)).
const KEPT: usize = 4;

impl<P> History<P> {
    /// A path at its start: the unloaded state at `lambda = 0`.
    pub fn new(start: P) -> History<P> {
        History {
            slots: [
                Some(Accepted {
                    lambda: 0.0,
                    point: start,
                }),
                None,
                None,
                None,
            ],
            len: 1,
            head: 0,
        }
    }

    /// The accepted point `k` before the last (`0`: the last itself), if kept.
    pub(super) fn back(&self, k: usize) -> Option<&Accepted<P>> {
        let n = self.len;
        if k < n {
            self.slots[(self.head + n - k) % n].as_ref()
        } else {
            None
        }
    }

    /// The last accepted point.
    pub fn last(&self) -> &Accepted<P> {
        match &self.slots[self.head] {
            Some(last) => last,
            None => unreachable!("a history always holds its last point"),
        }
    }

    /// The last accepted point, to take what a report keeps out of it.
    pub(super) fn last_mut(&mut self) -> &mut Accepted<P> {
        match &mut self.slots[self.head] {
            Some(last) => last,
            None => unreachable!("a history always holds its last point"),
        }
    }

    /// The accepted point before it (`None` at the start).
    pub fn before(&self) -> Option<&Accepted<P>> {
        self.back(1)
    }

    /// The one before `before`.
    pub(super) fn oldest(&self) -> Option<&Accepted<P>> {
        self.back(2)
    }

    /// The one before `oldest`, for [`Predictor::Cubic`](super::Predictor::Cubic).
    pub(super) fn eldest(&self) -> Option<&Accepted<P>> {
        self.back(3)
    }

    /// The last two accepted points, older first.
    pub fn iter(&self) -> impl Iterator<Item = &Accepted<P>> {
        self.before()
            .into_iter()
            .chain(std::iter::once(self.last()))
    }
}

impl<P: Clone> History<P> {
    /// Accepts `trial` at `lambda`, forgetting the oldest point kept, whose storage `trial`
    /// takes for the next attempt (so that following a path allocates only at its start).
    pub(super) fn accept(&mut self, lambda: f64, trial: &mut P) {
        if self.len < KEPT {
            let spare = self.last().point.clone();
            let point = std::mem::replace(trial, spare);
            self.slots[self.len] = Some(Accepted { lambda, point });
            self.head = self.len;
            self.len += 1;
        } else {
            self.head = (self.head + 1) % KEPT;
            if let Some(slot) = &mut self.slots[self.head] {
                slot.lambda = lambda;
                std::mem::swap(&mut slot.point, trial);
            }
        }
    }
}
