use super::*;

#[test]
fn lists_follow_inserts_and_moves() {
    let mut g = LinkedCells::new([0.0; 3], [5.0; 3], [true; 3], 1.0, 4);
    assert_eq!(g.shape.dims, [5, 5, 5]);
    for i in 0..4 {
        g.insert(i, [1, 2, 3]);
    }
    g.relocate(2, [0, 0, 0]);
    let cell = g.neighbourhood([1, 2, 3]).as_slice()[13];
    let mut members = vec![];
    let mut j = g.first(cell);
    while j != NONE {
        members.push(j);
        j = g.next(j);
    }
    let listed: Vec<u32> = g.particles(cell).map(|i| i as u32).collect();
    assert_eq!(listed, members, "the iterator follows the list");
    members.sort();
    assert_eq!(members, vec![0, 1, 3]);
    let moved = g.neighbourhood([0, 0, 0]).as_slice()[13];
    assert_eq!(g.particles(moved).collect::<Vec<_>>(), vec![2]);
    let empty = g.neighbourhood([4, 4, 4]).as_slice()[13];
    assert_eq!(g.particles(empty).count(), 0);
}

#[test]
fn interior_fast_path_matches_the_general_stencil() {
    let g = LinkedCells::new([0.0; 3], [6.0, 5.0, 4.0], [true, false, true], 1.0, 0);
    let c = [2, 2, 1];
    let fast = g.neighbourhood(c);
    let all = [-1, 0, 1];
    let slow = g.product(std::array::from_fn(|k| g.axis_neighbours(k, c[k], &all)));
    assert_eq!(fast.as_slice(), slow.as_slice());
    assert!(fast.iter().eq(slow.iter()));
    let base = g.interior(c).unwrap();
    assert_eq!(
        g.interior_neighbours(base).collect::<Vec<_>>(),
        fast.as_slice()
    );
    for axis in 0..3 {
        for dir in [-1, 1] {
            let layer = g.new_layer(c, axis, dir);
            let got: Vec<_> = g.interior_layer(base, axis, dir).collect();
            assert_eq!(got, layer.as_slice(), "axis {axis} dir {dir}");
            assert!(layer.iter().all(|(_, s)| s == [0.0; 3]));
        }
    }
    assert!(g.interior([0, 2, 1]).is_none() && g.interior([2, 2, 3]).is_none());
}

#[test]
fn neighbourhoods_wrap_with_image_shifts() {
    let g = LinkedCells::new([0.0; 3], [5.0, 2.0, 3.0], [true, true, false], 1.0, 0);
    assert_eq!(g.shape.dims, [5, 2, 3]);
    let n = g.neighbourhood([0, 0, 0]);
    // x: 3 (wrapping), y: 3 images of 2 cells, z: 2 (closed, no −1).
    assert_eq!(n.len(), 18);
    let mut v: Vec<_> = n.iter().map(|(c, s)| (c, s.map(|x| x as i64))).collect();
    v.sort();
    v.dedup();
    assert_eq!(v.len(), 18);
    assert!(
        n.iter()
            .any(|(c, s)| c as usize == 4 && s == [-5.0, 0.0, 0.0])
    );
    // Entering x = 0 moving −x (wrapped from 1): new layer at x = 4.
    let layer = g.new_layer([0, 0, 1], 0, -1);
    assert_eq!(layer.len(), 9);
    assert!(layer.as_slice().iter().all(|&c| c as usize % 5 == 4));
    assert_eq!(g.step(0, 0, -1), (4, 5.0));
    assert_eq!(g.faces(2, 0), (f64::NEG_INFINITY, 1.0));
}
