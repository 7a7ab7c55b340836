//! Bad input: a typed error that names what and where, and a tree left
//! exactly as it was.

use bvol_tree::{BoundError, Tree, TreeError};
use bvol_volumes::{Aabb, Sphere};
use glam::Vec3;

fn unit(x: f32) -> Aabb {
    Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 1.0, 1.0, 1.0))
}

fn bad_boxes() -> Vec<(Aabb, BoundError)> {
    let nan = Vec3::new(0.0, f32::NAN, 0.0);
    let inf = Vec3::new(0.0, 0.0, f32::INFINITY);
    vec![
        (Aabb::new(nan, Vec3::ONE), BoundError::NonFinite),
        (Aabb::new(Vec3::ZERO, nan), BoundError::NonFinite),
        (Aabb::new(-inf, Vec3::ONE), BoundError::NonFinite),
        (Aabb::new(Vec3::ZERO, inf), BoundError::NonFinite),
        (
            Aabb::new(Vec3::new(0.0, 2.0, 0.0), Vec3::ONE),
            BoundError::Inverted { axis: 1, min: 2.0, max: 1.0 },
        ),
    ]
}

/// A tree of a few boxes, and a snapshot of everything it answers.
fn sample() -> (Tree<Aabb>, impl Fn(&Tree<Aabb>)) {
    let bounds: Vec<Aabb> = (0..20).map(|i| unit(i as f32 * 0.7)).collect();
    let tree = Tree::from_bounds(&bounds).unwrap();
    let pairs = tree.pairs();
    let unchanged = move |t: &Tree<Aabb>| {
        t.validate().unwrap();
        assert_eq!(t.len(), 20);
        assert_eq!(t.pairs(), pairs);
        for (i, b) in bounds.iter().enumerate() {
            assert_eq!(t.bound(i as u32), Some(*b));
        }
    };
    (tree, unchanged)
}

#[test]
fn invalid_bounds_are_refused_everywhere() {
    let (mut tree, unchanged) = sample();
    for (b, reason) in bad_boxes() {
        let want = Err(TreeError::InvalidBound { id: 25, reason });
        assert_eq!(tree.insert(25, b), want);
        unchanged(&tree);
        assert_eq!(tree.set_bound(3, b), Err(TreeError::InvalidBound { id: 3, reason }));
        unchanged(&tree);
        // Many at once, enough for a batch build: the bad one is named.
        let many: Vec<(u32, Aabb)> =
            (30..60).map(|id| (id, if id == 41 { b } else { unit(id as f32) })).collect();
        assert_eq!(tree.insert_many(&many), Err(TreeError::InvalidBound { id: 41, reason }));
        unchanged(&tree);
        let mut frame: Vec<Aabb> = (0..20).map(|i| unit(i as f32)).collect();
        frame[7] = b;
        assert_eq!(tree.update(&frame), Err(TreeError::InvalidBound { id: 7, reason }));
        unchanged(&tree);
        assert_eq!(
            Tree::from_bounds(&frame).err(),
            Some(TreeError::InvalidBound { id: 7, reason })
        );
    }
}

#[test]
fn invalid_spheres_are_refused() {
    let mut tree = Tree::new();
    tree.insert(0, Sphere::new(Vec3::ZERO, 1.0)).unwrap();
    let cases = [
        (Sphere::new(Vec3::ZERO, -1.0), BoundError::NegativeRadius { radius: -1.0 }),
        (Sphere::new(Vec3::ZERO, f32::NAN), BoundError::NonFinite),
        (Sphere::new(Vec3::new(f32::INFINITY, 0.0, 0.0), 1.0), BoundError::NonFinite),
    ];
    for (s, reason) in cases {
        assert_eq!(tree.insert(1, s), Err(TreeError::InvalidBound { id: 1, reason }));
        assert_eq!(tree.set_bound(0, s), Err(TreeError::InvalidBound { id: 0, reason }));
        tree.validate().unwrap();
        assert_eq!(tree.bound(0), Some(Sphere::new(Vec3::ZERO, 1.0)));
        assert_eq!(tree.len(), 1);
    }
}

#[test]
fn unknown_duplicate_and_out_of_range_ids_are_refused() {
    let (mut tree, unchanged) = sample();
    assert_eq!(tree.remove(20), Err(TreeError::UnknownId { id: 20 }));
    assert_eq!(tree.remove(u32::MAX), Err(TreeError::UnknownId { id: u32::MAX }));
    assert_eq!(tree.set_bound(99, unit(0.0)), Err(TreeError::UnknownId { id: 99 }));
    assert_eq!(tree.insert(4, unit(0.0)), Err(TreeError::DuplicateId { id: 4 }));
    assert_eq!(
        tree.insert(Tree::<Aabb>::ID_LIMIT, unit(0.0)),
        Err(TreeError::IdOutOfRange { id: 1 << 28 })
    );
    assert_eq!(tree.insert(u32::MAX, unit(0.0)), Err(TreeError::IdOutOfRange { id: u32::MAX }));
    let out_of_range = [(30, unit(0.0)), (Tree::<Aabb>::ID_LIMIT + 1, unit(0.0))];
    assert_eq!(tree.insert_many(&out_of_range), Err(TreeError::IdOutOfRange { id: (1 << 28) + 1 }));
    let present = [(30, unit(0.0)), (31, unit(0.0)), (4, unit(0.0))];
    assert_eq!(tree.insert_many(&present), Err(TreeError::DuplicateId { id: 4 }));
    let twice: Vec<(u32, Aabb)> = [30, 31, 32, 31, 30].map(|id| (id, unit(0.0))).to_vec();
    assert_eq!(tree.insert_many(&twice), Err(TreeError::DuplicateId { id: 31 }));
    unchanged(&tree);
    tree.remove(4).unwrap();
    assert_eq!(tree.remove(4), Err(TreeError::UnknownId { id: 4 }));
    let dup = Tree::build(Default::default(), [(1, unit(0.0)), (1, unit(1.0))]);
    assert_eq!(dup.err(), Some(TreeError::DuplicateId { id: 1 }));
}

/// A frame with bad bounds far apart (in different chunks of the check,
/// which is parallel from 65 536 bounds) names the first, whatever the
/// thread count, and changes nothing.
#[test]
fn a_frame_names_its_first_bad_bound_on_any_thread_count() {
    for n in [50_000, 100_000] {
        frame_names_its_first_bad_bound(n);
    }
}

fn frame_names_its_first_bad_bound(n: usize) {
    let good: Vec<Aabb> = (0..n).map(|i| unit((i % 200) as f32 * 2.0)).collect();
    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut tree = Tree::from_bounds(&good).unwrap();
            let before = tree.pairs();
            let mut frame = good.clone();
            frame[41_000] = Aabb::new(Vec3::splat(f32::NAN), Vec3::ONE);
            frame[20_001] = Aabb::new(Vec3::new(0.0, 2.0, 0.0), Vec3::new(1.0, 1.0, 1.0));
            let inverted = BoundError::Inverted { axis: 1, min: 2.0, max: 1.0 };
            let want = TreeError::InvalidBound { id: 20_001, reason: inverted };
            assert_eq!(tree.update(&frame), Err(want), "{threads} threads");
            assert_eq!(tree.pairs(), before, "{threads} threads");
            tree.validate().unwrap();
        });
    }
}

#[test]
fn errors_say_what_and_where() {
    let inverted = TreeError::InvalidBound {
        id: 7,
        reason: BoundError::Inverted { axis: 1, min: 2.0, max: 1.0 },
    };
    assert_eq!(inverted.to_string(), "the bound of id 7 has min > max on axis y: 2 > 1");
    let nan = TreeError::InvalidBound { id: 3, reason: BoundError::NonFinite };
    assert_eq!(nan.to_string(), "the bound of id 3 has a NaN or infinite coordinate");
    assert_eq!(TreeError::UnknownId { id: 5 }.to_string(), "id 5 is not in the tree");
    assert_eq!(
        TreeError::DuplicateId { id: 5 }.to_string(),
        "id 5 is already in the tree, or given twice"
    );
    assert!(TreeError::IdOutOfRange { id: u32::MAX }.to_string().contains("4294967295"));
}

#[test]
fn extreme_but_finite_bounds_work() {
    // Huge, tiny, far and degenerate boxes: no overflow to NaN, exact pairs.
    let bounds = [
        Aabb::new(Vec3::splat(-3e38), Vec3::splat(3e38)),
        Aabb::new(Vec3::splat(1e-30), Vec3::splat(2e-30)),
        Aabb::new(Vec3::splat(1e30), Vec3::splat(1e30)),
        Aabb::new(Vec3::ZERO, Vec3::ZERO),
        Aabb::new(Vec3::splat(-1e-30), Vec3::ZERO),
        Aabb::new(Vec3::splat(1e38), Vec3::splat(3e38)),
    ];
    let mut tree = Tree::new();
    for (i, b) in bounds.iter().enumerate() {
        tree.insert(i as u32, *b).unwrap();
        tree.validate().unwrap();
    }
    let mut pairs = tree.pairs();
    pairs.sort_unstable();
    // Box 0 holds all; the point at 0 touches [-1e-30, 0]; [1e-30, 2e-30]
    // touches neither; [1e38, 3e38] only box 0.
    assert_eq!(pairs, vec![(0, 1), (0, 2), (0, 3), (0, 4), (0, 5), (3, 4)]);
    tree.update(&bounds.map(|b| Aabb::new(b.min * 0.5, b.max * 0.5))).unwrap();
    tree.validate().unwrap();
    tree.rebuild();
    tree.validate().unwrap();
    let mut pairs = tree.pairs();
    pairs.sort_unstable();
    assert_eq!(pairs, vec![(0, 1), (0, 2), (0, 3), (0, 4), (0, 5), (3, 4)]);
}
