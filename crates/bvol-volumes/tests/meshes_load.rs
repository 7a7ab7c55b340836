mod common;

#[test]
fn shipped_meshes_match_their_reference_vertex_counts() {
    let refs = common::references();
    assert_eq!(refs.len(), 5);
    for r in refs {
        assert_eq!(common::mesh(&r.name).len(), r.vertices, "{}", r.name);
    }
}
