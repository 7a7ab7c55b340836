//! STUB: k-DOPs (being written).
/// k-DOP.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kdop<const N: usize> {
    /// Lower slab bounds.
    pub min: [f32; N],
    /// Upper slab bounds.
    pub max: [f32; N],
}
/// 6-DOP.
pub type Kdop6 = Kdop<3>;
/// 14-DOP.
pub type Kdop14 = Kdop<7>;
/// 18-DOP.
pub type Kdop18 = Kdop<9>;
/// 26-DOP.
pub type Kdop26 = Kdop<13>;
