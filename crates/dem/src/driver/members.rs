//! Which particles the Verlet driver moves: all of them (MD), or those of a mask (the
//! hybrid engine's time-driven particles).

/// The particles a [`super::Verlet`] step moves and finds contacts between. A pair
/// counts only if both are members; a member's contacts with walls always count.
pub trait Members: Copy + Send + Sync {
    /// Whether every particle is a member (decided at compile time, so that MD's loops
    /// carry no test).
    const ALL: bool;
    /// Whether particle `i` is a member.
    fn contains(self, i: usize) -> bool;
}

/// Every particle (MD).
#[derive(Debug, Clone, Copy, Default)]
pub struct All;

impl Members for All {
    const ALL: bool = true;

    #[inline(always)]
    fn contains(self, _: usize) -> bool {
        true
    }
}

/// The particles whose entry is true.
impl Members for &[bool] {
    const ALL: bool = false;

    #[inline(always)]
    fn contains(self, i: usize) -> bool {
        self[i]
    }
}
