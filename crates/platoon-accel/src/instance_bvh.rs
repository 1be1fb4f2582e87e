//! The top level: a BVH over the instances' world boxes, rebuilt every generation.

use obvhs::aabb::Aabb;

use super::bvh::{item, BvhNode, FlatBvh};

/// The top level over instance boxes (every box finite, see [`placeable`](platoon_scene::placeable::placeable)), rebuilt every
/// generation: a top-down median split on the longest axis of the centroids, one instance per
/// leaf. It takes a few microseconds per hundred instances where obvhs' fastest PLOC preset took
/// 0.3 ms for a thousand (measured by `platoon bench dynamic`); a top level is small and its
/// quality matters less than the bottom levels'.
pub fn build_instance_bvh(boxes: &[Aabb]) -> FlatBvh {
    if boxes.is_empty() {
        return FlatBvh::default();
    }
    let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
    let mut nodes = Vec::with_capacity(boxes.len().saturating_sub(1));
    let (bounds, root) = median_split(&mut order, 0, boxes, &mut nodes);
    FlatBvh {
        nodes,
        root,
        order,
        bounds: (bounds.min.into(), bounds.max.into()),
    }
}

/// The subtree over `ids` (which sit at `offset` in the final order), reordered in place.
fn median_split(
    ids: &mut [u32],
    offset: usize,
    boxes: &[Aabb],
    nodes: &mut Vec<BvhNode>,
) -> (Aabb, u32) {
    if let [only] = ids {
        return (boxes[*only as usize], item(offset as u32, 1));
    }
    let mut centroids = Aabb::empty();
    for &i in ids.iter() {
        centroids.extend(boxes[i as usize].center());
    }
    let extent = centroids.diagonal();
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = ids.len() / 2;
    ids.select_nth_unstable_by(mid, |&a, &b| {
        let (ca, cb) = (boxes[a as usize].center(), boxes[b as usize].center());
        ca[axis].total_cmp(&cb[axis]).then(a.cmp(&b))
    });
    let index = nodes.len();
    nodes.push(BvhNode::default());
    let (left, right) = ids.split_at_mut(mid);
    let (a, ia) = median_split(left, offset, boxes, nodes);
    let (b, ib) = median_split(right, offset + mid, boxes, nodes);
    nodes[index] = BvhNode::pair(
        (a.min.into(), a.max.into(), ia),
        (b.min.into(), b.max.into(), ib),
    );
    (a.union(&b), item(index as u32, 0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::unpack_item;
    use glam::{Vec3, Vec3A};

    #[test]
    fn the_top_level_names_every_instance_once_inside_its_parents_boxes() {
        let boxes: Vec<Aabb> = (0..37)
            .map(|i| {
                let p = Vec3A::new((i * 7 % 11) as f32, (i % 5) as f32, (i / 9) as f32);
                Aabb::new(p, p + Vec3A::splat(0.5))
            })
            .collect();
        let bvh = build_instance_bvh(&boxes);
        let mut seen = vec![0; boxes.len()];
        for (i, c) in bvh.leaves() {
            assert_eq!(c, 1);
            seen[bvh.order[i as usize] as usize] += 1;
        }
        assert!(seen.iter().all(|&s| s == 1));
        // Each child box contains the boxes of everything below it.
        fn check(bvh: &FlatBvh, it: u32, lo: Vec3, hi: Vec3, boxes: &[Aabb]) {
            let (index, count) = unpack_item(it);
            if count > 0 {
                let b = boxes[bvh.order[index as usize] as usize];
                assert!(Vec3::from(b.min).cmpge(lo).all() && Vec3::from(b.max).cmple(hi).all());
                return;
            }
            let n = bvh.nodes[index as usize];
            for (mn, mx, item) in [(n.min0, n.max0, n.item0), (n.min1, n.max1, n.item1)] {
                let (mn, mx) = (Vec3::from_array(mn), Vec3::from_array(mx));
                assert!(mn.cmpge(lo).all() && mx.cmple(hi).all());
                check(bvh, item, mn, mx, boxes);
            }
        }
        let (lo, hi) = bvh.bounds();
        check(&bvh, bvh.root, lo, hi, &boxes);
        let one = build_instance_bvh(&boxes[..1]);
        assert!(one.nodes.is_empty() && unpack_item(one.root) == (0, 1));
    }
}
