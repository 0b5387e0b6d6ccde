//! Generational arenas: objects of a world are addressed by handles that stay
//! valid until the object is removed (Rapier-style sets).
use serde::{Deserialize, Serialize};

macro_rules! handle {
    ($name:ident, $what:literal) => {
        #[doc = concat!("Handle of a ", $what, " in a world.")]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
        pub struct $name {
            pub index: u32,
            pub generation: u32,
        }
        impl From<Index> for $name {
            fn from(i: Index) -> Self {
                $name { index: i.0, generation: i.1 }
            }
        }
        impl From<$name> for Index {
            fn from(h: $name) -> Index {
                Index(h.index, h.generation)
            }
        }
    };
}
handle!(RodHandle, "rod");
handle!(ConstraintHandle, "constraint");
handle!(LoadHandle, "load");
handle!(BeadHandle, "bead");
handle!(ClipHandle, "clip");

/// (slot, generation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Index(pub u32, pub u32);

#[derive(Clone, Debug, Serialize, Deserialize)]
struct Slot<T> {
    generation: u32,
    item: Option<T>,
}

/// A generational arena with a free list: insert, remove and lookup are
/// O(1), and a removed slot is reused with a bumped generation, so stale
/// handles never name a new object. Deserialisation is deterministic: the
/// free list is serialised with the slots.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Arena<T> {
    slots: Vec<Slot<T>>,
    /// Empty slots, reused last-freed first.
    #[serde(default)]
    free: Vec<u32>,
    #[serde(default)]
    len: usize,
}

impl<T> Default for Arena<T> {
    fn default() -> Self {
        Arena { slots: Vec::new(), free: Vec::new(), len: 0 }
    }
}

impl<T> Arena<T> {
    pub fn insert(&mut self, item: T) -> Index {
        self.len += 1;
        if let Some(i) = self.free.pop() {
            let s = &mut self.slots[i as usize];
            s.generation = s.generation.wrapping_add(1);
            s.item = Some(item);
            return Index(i, s.generation);
        }
        self.slots.push(Slot { generation: 0, item: Some(item) });
        Index(self.slots.len() as u32 - 1, 0)
    }
    pub fn remove(&mut self, i: Index) -> Option<T> {
        let s = self.slots.get_mut(i.0 as usize)?;
        if s.generation != i.1 {
            return None;
        }
        let item = s.item.take()?;
        self.free.push(i.0);
        self.len -= 1;
        Some(item)
    }
    pub fn get(&self, i: Index) -> Option<&T> {
        self.slots.get(i.0 as usize).filter(|s| s.generation == i.1).and_then(|s| s.item.as_ref())
    }
    pub fn get_mut(&mut self, i: Index) -> Option<&mut T> {
        self.slots.get_mut(i.0 as usize).filter(|s| s.generation == i.1).and_then(|s| s.item.as_mut())
    }
    /// `f` of every live item on rayon's pool, into `out` in slot order
    /// (the order of [`Arena::iter`]); a caller that sums `out` in order
    /// gets the serial sum bit for bit. Written slot by slot, then the
    /// free slots' entries squeezed out: allocation-free once `out` has
    /// seen the arena's capacity (a filtered `par_extend` gathers its
    /// pieces in a linked list of fresh vectors, about 120 allocations per
    /// step of 400 rods).
    pub(crate) fn par_map_into<U: Send + Copy + Default>(&self, out: &mut Vec<U>, f: impl Fn(&T) -> U + Sync + Send)
    where
        T: Sync,
    {
        use rayon::prelude::*;
        out.clear();
        out.resize(self.slots.len(), U::default());
        out.par_iter_mut().zip(self.slots.par_iter()).for_each(|(o, s)| {
            if let Some(t) = s.item.as_ref() {
                *o = f(t);
            }
        });
        let mut live = 0;
        for (i, s) in self.slots.iter().enumerate() {
            if s.item.is_some() {
                out[live] = out[i];
                live += 1;
            }
        }
        out.truncate(live);
    }
    /// Live items in slot order.
    pub fn iter(&self) -> impl Iterator<Item = (Index, &T)> {
        self.slots.iter().enumerate().filter_map(|(i, s)| s.item.as_ref().map(|t| (Index(i as u32, s.generation), t)))
    }
    pub fn iter_mut(&mut self) -> impl Iterator<Item = (Index, &mut T)> {
        self.slots
            .iter_mut()
            .enumerate()
            .filter_map(|(i, s)| s.item.as_mut().map(|t| (Index(i as u32, s.generation), t)))
    }
    pub fn len(&self) -> usize {
        self.len
    }
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// Number of slots (live or free): an upper bound on slot indices.
    pub fn capacity(&self) -> usize {
        self.slots.len()
    }
    /// Rebuilds the free list and count from the slots, and checks them (after
    /// deserialising untrusted data).
    pub(crate) fn repair(&mut self) -> crate::error::Result<()> {
        self.len = self.slots.iter().filter(|s| s.item.is_some()).count();
        self.free = self.slots.iter().enumerate().filter(|(_, s)| s.item.is_none()).map(|(i, _)| i as u32).rev().collect();
        if self.slots.len() > u32::MAX as usize {
            return Err(crate::error::Error::invalid("arena size", self.slots.len(), "at most 2^32 - 1 slots"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn free_list_reuses_slots_with_new_generations() {
        let mut a = Arena::default();
        let (x, y) = (a.insert(1), a.insert(2));
        assert_eq!(a.len(), 2);
        assert_eq!(a.remove(x), Some(1));
        assert_eq!(a.remove(x), None, "a stale handle removes nothing");
        let z = a.insert(3);
        assert_eq!((z.0, z.1), (x.0, x.1 + 1), "slot reused, generation bumped");
        assert!(a.get(x).is_none());
        assert_eq!(a.get(z), Some(&3));
        assert_eq!(a.get(y), Some(&2));
        assert_eq!(a.len(), 2);
    }
}
