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

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Arena<T> {
    slots: Vec<Slot<T>>,
}

impl<T> Default for Arena<T> {
    fn default() -> Self {
        Arena { slots: Vec::new() }
    }
}

impl<T> Arena<T> {
    pub fn insert(&mut self, item: T) -> Index {
        if let Some(i) = self.slots.iter().position(|s| s.item.is_none()) {
            self.slots[i].generation += 1;
            self.slots[i].item = Some(item);
            return Index(i as u32, self.slots[i].generation);
        }
        self.slots.push(Slot { generation: 0, item: Some(item) });
        Index(self.slots.len() as u32 - 1, 0)
    }
    pub fn remove(&mut self, i: Index) -> Option<T> {
        let s = self.slots.get_mut(i.0 as usize)?;
        if s.generation != i.1 {
            return None;
        }
        s.item.take()
    }
    pub fn get(&self, i: Index) -> Option<&T> {
        self.slots.get(i.0 as usize).filter(|s| s.generation == i.1).and_then(|s| s.item.as_ref())
    }
    pub fn get_mut(&mut self, i: Index) -> Option<&mut T> {
        self.slots.get_mut(i.0 as usize).filter(|s| s.generation == i.1).and_then(|s| s.item.as_mut())
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
        self.slots.iter().filter(|s| s.item.is_some()).count()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
