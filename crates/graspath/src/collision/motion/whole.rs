//! [`ArmInScene::check`]: a solved motion checked sample by sample and, between samples, by
//! the interval bound of the parent module's documentation, with its clearance measured.

use super::*;

/// Buffers reused from sample to sample of one check.
struct Buffers<'a> {
    placed: Vec<Placed<'a>>,
    placed_before: Vec<Placed<'a>>,
    known: Vec<Known>,
    known_before: Vec<Known>,
    /// Index in the clearance entries of each pair's value at this sample and the one before.
    entry: Vec<usize>,
    entry_before: Vec<usize>,
    /// Per slot, how far it may move over the current interval (m).
    moved: Vec<f64>,
    /// The joint axes at this sample and the one before (world frame).
    axes: JointAxes,
    axes_before: JointAxes,
    mid_frames: Vec<IsometryMatrix3<f64>>,
    mid_axes: JointAxes,
}

impl ArmInScene<'_> {
    /// Checks a whole motion (see the module documentation).
    pub fn check(&self, motion: &WholeMotion<'_>) -> MotionCheck {
        let chain = self.arm.chain();
        let slots = Slots::new(*self, &motion.object);
        let n = motion.q.len();
        let links = chain.link_names().len();
        let mut frames = vec![vec![IsometryMatrix3::identity(); links]; n];
        for (q, f) in motion.q.iter().zip(&mut frames) {
            if chain.link_frames_into(q, f).is_err() {
                // Configurations come from the IK inside the limits; a bad one is no motion.
                return MotionCheck {
                    hit: None,
                    clearance: None,
                };
            }
        }
        let stretches = motion.object.stretches(n);
        let mut clearance_entries: Vec<(Known, usize, ObjectAt, usize)> = Vec::new();
        let mut buffers = Buffers {
            placed: Vec::new(),
            placed_before: Vec::new(),
            known: Vec::new(),
            known_before: Vec::new(),
            entry: Vec::new(),
            entry_before: Vec::new(),
            moved: Vec::new(),
            axes: Vec::new(),
            axes_before: Vec::new(),
            mid_frames: vec![IsometryMatrix3::identity(); links],
            mid_axes: Vec::new(),
        };
        for (at, samples) in stretches {
            let pairs = slots.pairs(at);
            if pairs.is_empty() {
                continue;
            }
            let mut previous: Option<usize> = None;
            for s in samples {
                let b = &mut buffers;
                slots.place_into(&frames[s], at, &mut b.placed);
                self.arm
                    .sweep()
                    .axes_into(&slots.world_from_base, &frames[s], &mut b.axes);
                b.known.clear();
                b.entry.clear();
                for (p, pair) in pairs.iter().enumerate() {
                    let (x, y) = (&b.placed[pair.a], &b.placed[pair.b]);
                    let k = measure(pair, x, y, Level::Sphere);
                    if pair.violated_by(k.value) {
                        return MotionCheck {
                            hit: Some(hit(pair, x, y, k.value, s, false)),
                            clearance: None,
                        };
                    }
                    b.entry.push(clearance_entries.len());
                    if pair.scene {
                        clearance_entries.push((k, s, at, p));
                    }
                    b.known.push(k);
                }
                if let Some(r) = previous {
                    slots.displacements_into(
                        at,
                        (&b.placed_before, &b.axes_before),
                        (&b.placed, &b.axes),
                        (&motion.q[r], &motion.q[s]),
                        &mut b.moved,
                    );
                    for (p, pair) in pairs.iter().enumerate() {
                        let bound = b.moved[pair.a] + b.moved[pair.b];
                        let (mut before, mut now) = (b.known_before[p], b.known[p]);
                        let clear = 2.0 * pair.required;
                        // Refine the ends until the interval is proven clear or both are exact.
                        while before.value + now.value - bound <= clear
                            && (before.level < Level::Exact || now.level < Level::Exact)
                        {
                            if before.level < Level::Exact {
                                let (x, y) = (&b.placed_before[pair.a], &b.placed_before[pair.b]);
                                before = measure(pair, x, y, before.level.next());
                            }
                            if now.level < Level::Exact {
                                let (x, y) = (&b.placed[pair.a], &b.placed[pair.b]);
                                now = measure(pair, x, y, now.level.next());
                            }
                        }
                        b.known[p] = now;
                        if pair.scene {
                            clearance_entries[b.entry_before[p]].0 = before;
                            clearance_entries[b.entry[p]].0 = now;
                        }
                        if before.value + now.value - bound > clear {
                            continue;
                        }
                        let interval = Interval {
                            slots: &slots,
                            pair,
                            at,
                        };
                        if let Some(h) = interval.search(
                            (&motion.q[r], before.value),
                            (&motion.q[s], now.value),
                            bound,
                            (&mut b.mid_frames, &mut b.mid_axes),
                        ) {
                            return MotionCheck {
                                hit: Some(CollisionHit { sample: r, ..h }),
                                clearance: None,
                            };
                        }
                    }
                }
                std::mem::swap(&mut b.placed, &mut b.placed_before);
                std::mem::swap(&mut b.known, &mut b.known_before);
                std::mem::swap(&mut b.entry, &mut b.entry_before);
                std::mem::swap(&mut b.axes, &mut b.axes_before);
                previous = Some(s);
            }
        }
        let clearance = (!self.scene.is_empty())
            .then(|| exact_minimum(&slots, &frames, &mut clearance_entries));
        MotionCheck {
            hit: None,
            clearance,
        }
    }
}

/// The smallest exact distance among `entries` (lower bounds or exact values), refining only
/// entries whose bound is below the best exact value found (branch and bound: each
/// refinement raises an entry's value, and an entry is exact after at most three).
fn exact_minimum(
    slots: &Slots<'_>,
    frames: &[Vec<IsometryMatrix3<f64>>],
    entries: &mut [(Known, usize, ObjectAt, usize)],
) -> f64 {
    let mut best = entries
        .iter()
        .filter(|e| e.0.level == Level::Exact)
        .map(|e| e.0.value)
        .fold(f64::INFINITY, f64::min);
    let mut pairs_of: Vec<(ObjectAt, Vec<Pair>)> = Vec::new();
    loop {
        let next = entries
            .iter_mut()
            .filter(|e| e.0.level < Level::Exact && e.0.value < best)
            .min_by(|x, y| x.0.value.total_cmp(&y.0.value));
        let Some(entry) = next else {
            break;
        };
        let (known, s, at, p) = *entry;
        if !pairs_of.iter().any(|(a, _)| *a == at) {
            pairs_of.push((at, slots.pairs(at)));
        }
        let pairs = &pairs_of
            .iter()
            .find(|(a, _)| *a == at)
            .expect("just added")
            .1;
        let pair = &pairs[p];
        let x = slots.slot(pair.a, &frames[s], at);
        let y = slots.slot(pair.b, &frames[s], at);
        let mut k = measure(pair, &x, &y, known.level.next());
        if k.level == Level::Exact {
            best = best.min(k.value);
        } else {
            // Both are lower bounds: keep the larger.
            k.value = k.value.max(known.value);
        }
        entry.0 = k;
    }
    best
}

/// The continuous check of one pair over one interval.
struct Interval<'s, 'a> {
    slots: &'s Slots<'a>,
    pair: &'s Pair,
    at: ObjectAt,
}

impl Interval<'_, '_> {
    /// Searches `[qa, qb]`, with lower bounds (or exact distances) `da`, `db` at its ends,
    /// neither breaking the requirement, and displacement bound `bound`, for a configuration
    /// closer than required.
    fn search(
        &self,
        (qa, da): (&[f64], f64),
        (qb, db): (&[f64], f64),
        bound: f64,
        (frames, axes): (&mut [IsometryMatrix3<f64>], &mut JointAxes),
    ) -> Option<CollisionHit> {
        let pair = self.pair;
        let clear = 2.0 * pair.required;
        if da + db - bound > clear || bound < self.slots.setup.options.resolution {
            return None;
        }
        let mid: Vec<f64> = qa.iter().zip(qb).map(|(a, b)| 0.5 * (a + b)).collect();
        let sweep = self.slots.setup.arm.sweep();
        let chain = self.slots.setup.arm.chain();
        chain.link_frames_into(&mid, frames).ok()?;
        sweep.axes_into(&self.slots.world_from_base, frames, axes);
        let x = self.slots.slot(pair.a, frames, self.at);
        let y = self.slots.slot(pair.b, frames, self.at);
        // Both halves end at the middle and span half the joint change: the near bound from
        // the middle holds for each.
        let half = self
            .slots
            .displacement(pair.a, self.at, &x, axes, (qa, &mid))
            + self
                .slots
                .displacement(pair.b, self.at, &y, axes, (qa, &mid));
        let mut dm = measure(pair, &x, &y, Level::Cover);
        while dm.level < Level::Exact {
            if da + dm.value - half > clear && dm.value + db - half > clear {
                // A bound short of the exact distance proves both halves clear.
                return None;
            }
            dm = measure(pair, &x, &y, dm.level.next());
        }
        if pair.violated_by(dm.value) {
            return Some(hit(pair, &x, &y, dm.value, 0, true));
        }
        self.search((qa, da), (&mid, dm.value), half, (frames, axes))
            .or_else(|| self.search((&mid, dm.value), (qb, db), half, (frames, axes)))
    }
}
