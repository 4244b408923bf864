//! Bounded arrays for EPA's polytope: on the stack (`ArrayVec`) for the common case, or in a
//! heap buffer of fixed capacity ([`Capped`]), reserved once per thread and reused, for the
//! rare overlaps that need more support points than the stack holds.

use arrayvec::ArrayVec;
use std::ops::{Deref, DerefMut};

/// A vector of bounded capacity: its elements as a slice, and pushes that never grow it.
pub(super) trait Slots<T>: Deref<Target = [T]> + DerefMut {
    /// Appends `t`; false (and nothing changed) when full.
    fn push_slot(&mut self, t: T) -> bool;
    fn pop_slot(&mut self) -> Option<T>;
    fn clear_slots(&mut self);
    /// How many more elements fit.
    fn room(&self) -> usize;
}

impl<T, const N: usize> Slots<T> for ArrayVec<T, N> {
    #[inline]
    fn push_slot(&mut self, t: T) -> bool {
        self.try_push(t).is_ok()
    }
    #[inline]
    fn pop_slot(&mut self) -> Option<T> {
        self.pop()
    }
    #[inline]
    fn clear_slots(&mut self) {
        self.clear()
    }
    #[inline]
    fn room(&self) -> usize {
        N - self.len()
    }
}

/// A `Vec` that never grows past the capacity it was made with (so it never reallocates).
pub(super) struct Capped<T> {
    items: Vec<T>,
    cap: usize,
}

impl<T> Capped<T> {
    pub(super) fn with_capacity(cap: usize) -> Self {
        Capped {
            items: Vec::with_capacity(cap),
            cap,
        }
    }
}

impl<T> Deref for Capped<T> {
    type Target = [T];
    #[inline]
    fn deref(&self) -> &[T] {
        &self.items
    }
}

impl<T> DerefMut for Capped<T> {
    #[inline]
    fn deref_mut(&mut self) -> &mut [T] {
        &mut self.items
    }
}

impl<T> Slots<T> for Capped<T> {
    #[inline]
    fn push_slot(&mut self, t: T) -> bool {
        if self.items.len() < self.cap {
            self.items.push(t);
            true
        } else {
            false
        }
    }
    #[inline]
    fn pop_slot(&mut self) -> Option<T> {
        self.items.pop()
    }
    #[inline]
    fn clear_slots(&mut self) {
        self.items.clear()
    }
    #[inline]
    fn room(&self) -> usize {
        self.cap - self.items.len()
    }
}
