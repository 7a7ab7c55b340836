//! The broadphase seam: the dynamic tree against the brute-force reference,
//! call by call, through random inserts, removals, moves (one by one and all
//! at once) and bad input: the same pairs within a set and between two, the
//! same nearest ray hit, the same leaves in a region, the same errors.

use std::collections::BTreeSet;

use bvol::tree::Tree;
use bvol::volumes::{Aabb, Ray};
use bvol::{Broadphase, BruteForce};
use glam::Vec3;
use proptest::prelude::*;

/// One call on both sets (`second` picks the other set of the pair).
#[derive(Clone, Debug)]
enum Call {
    Insert { second: bool, leaves: Vec<(u32, Aabb)> },
    Remove { second: bool, id: u32 },
    Move { second: bool, moved: Vec<(u32, Aabb)> },
    MoveAll { second: bool, boxes: Vec<Aabb> },
}

/// Ids from a small range, so that calls often name leaves in the set.
const IDS: u32 = 24;

/// Boxes in a cube of side 10, of sizes up to 3: dense enough for overlaps;
/// now and then one with a NaN corner, which both must refuse.
fn any_box() -> impl Strategy<Value = Aabb> {
    prop_oneof![
        20 => (prop::array::uniform3(0.0f32..10.0), prop::array::uniform3(0.0f32..3.0))
            .prop_map(|(at, size)| {
                let min = Vec3::from_array(at);
                Aabb::new(min, min + Vec3::from_array(size))
            }),
        1 => Just(Aabb::new(Vec3::NAN, Vec3::ONE)),
    ]
}

/// A few leaves, ids now and then repeated, or at or past the set's limit.
fn any_leaves() -> impl Strategy<Value = Vec<(u32, Aabb)>> {
    let id = prop_oneof![20 => 0..IDS, 1 => Just(Tree::<Aabb>::ID_LIMIT)];
    prop::collection::vec((id, any_box()), 0..8)
}

fn any_call() -> impl Strategy<Value = Call> {
    prop_oneof![
        4 => (any::<bool>(), any_leaves()).prop_map(|(second, leaves)| Call::Insert { second, leaves }),
        2 => (any::<bool>(), 0..IDS).prop_map(|(second, id)| Call::Remove { second, id }),
        2 => (any::<bool>(), any_leaves()).prop_map(|(second, moved)| Call::Move { second, moved }),
        1 => (any::<bool>(), prop::collection::vec(any_box(), 0..=IDS as usize))
            .prop_map(|(second, boxes)| Call::MoveAll { second, boxes }),
    ]
}

/// Applies a call to one of a pair of sets; the result, as a string (the
/// two kinds share the tree's error type, but the string is what a user
/// reads).
fn call<B: Broadphase>(sets: &mut [B; 2], c: &Call) -> Result<(), String> {
    let e = |r: Result<(), B::Error>| r.map_err(|e| e.to_string());
    match c {
        Call::Insert { second, leaves } => e(sets[*second as usize].insert_many(leaves)),
        Call::Remove { second, id } => e(sets[*second as usize].remove(*id)),
        Call::Move { second, moved } => e(sets[*second as usize].update_moved(moved)),
        Call::MoveAll { second, boxes } => e(sets[*second as usize].update_from(boxes)),
    }
}

/// What a pair of sets answers: pairs within the first, between the two,
/// the nearest hit of a ray on the boxes, and the leaves in a region.
fn answers<B: Broadphase>(sets: &[B; 2], ray: &Ray, region: &Aabb) -> Answers {
    let mut within = Vec::new();
    sets[0].pairs_into(&mut within);
    let mut between = vec![(u32::MAX, u32::MAX)];
    sets[0].pairs_with(&sets[1], &mut between);
    assert_eq!(between.remove(0), (u32::MAX, u32::MAX), "pairs_with appends");
    let mut found = BTreeSet::new();
    sets[1].query(region, |id| assert!(found.insert(id), "{id} found twice"));
    Answers {
        within: within.into_iter().collect(),
        between: between.into_iter().collect(),
        hit: sets[0].ray_cast(ray, 20.0, |_, t| Some(t)),
        found,
        lens: [sets[0].len(), sets[1].len()],
    }
}

#[derive(Debug, PartialEq)]
struct Answers {
    within: BTreeSet<(u32, u32)>,
    between: BTreeSet<(u32, u32)>,
    hit: Option<(u32, f32)>,
    found: BTreeSet<u32>,
    lens: [usize; 2],
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// After every call, the tree and the brute force agree on everything a
    /// world asks of a broadphase; the pairs within a set come each once,
    /// lower id first.
    #[test]
    fn tree_answers_as_brute_force(
        calls in prop::collection::vec(any_call(), 1..32),
        from in prop::array::uniform3(-2.0f32..12.0),
        to in prop::array::uniform3(0.0f32..10.0),
    ) {
        let mut trees: [Tree<Aabb>; 2] = Default::default();
        let mut brutes: [BruteForce; 2] = Default::default();
        let (from, to) = (Vec3::from_array(from), Vec3::from_array(to));
        let ray = Ray::new(from, (to - from).try_normalize().unwrap_or(Vec3::X));
        let region = Aabb::new(from.min(to), from.max(to));
        for c in &calls {
            prop_assert_eq!(call(&mut trees, c), call(&mut brutes, c), "{:?}", c);
            let mut within = Vec::new();
            Broadphase::pairs_into(&trees[0], &mut within);
            prop_assert!(within.iter().all(|&(a, b)| a < b));
            prop_assert_eq!(within.len(), within.iter().collect::<BTreeSet<_>>().len());
            prop_assert_eq!(answers(&trees, &ray, &region), answers(&brutes, &ray, &region));
        }
    }
}
