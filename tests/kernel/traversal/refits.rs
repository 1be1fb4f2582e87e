//! A deforming mesh's bottom level follows it as the core's BVH of it does: built once
//! compacted, built again to be refitted at its first deformation, refitted in place after,
//! built again where the core built its BVH again (`Commit::rebuilt`); each image the bits of a
//! tracer made fresh on the pose.

use super::*;
use platoon::core::flatten::commit::Commit;

#[test]
fn a_deforming_meshs_bottom_level_is_refitted_and_built_again_where_the_core_rebuilt() {
    let rest = cesium_at(0.0);
    let mut tracer = tracer_by(&rest, Traversal::RayQuery);
    let start = tracer.structure_counts().expect("structures");
    eprintln!("built: {start:?}");
    let meshes = rest
        .gpu
        .regions
        .iter()
        .filter(|r| r.triangle_count > 0)
        .count();
    assert_eq!(start.built, meshes as u64, "{start:?}");
    assert!(
        0 < start.compacted_to && start.compacted_to <= start.compacted_from,
        "compaction: {start:?}"
    );
    let mut before = rest;
    // (time, whether the core built the skin's BVH again, (built, refitted) by this step)
    let steps = [
        (0.3, false, (1, 0)),
        (0.6, false, (1, 1)),
        (0.9, true, (2, 1)),
        (1.2, false, (2, 2)),
    ];
    for (time, rebuilt, (built, refitted)) in steps {
        let after = cesium_at(time);
        let mut commit = Commit::between(&before.gpu, &after.gpu);
        if rebuilt {
            commit.rebuilt = (0..after.gpu.regions.len() as u32).collect();
        }
        tracer.apply_commit(&commit).expect("the commit");
        let counts = tracer.structure_counts().expect("structures");
        assert_eq!(
            (counts.built - start.built, counts.refitted),
            (built, refitted),
            "at {time} s: {counts:?}"
        );
        let params = FrameParams::new(24, 24, 4, after.camera);
        let fresh = render_with(&mut tracer_by(&after, Traversal::RayQuery), &params);
        assert!(
            render_with(&mut tracer, &params) == fresh,
            "at {time} s: the refitted structures' image differs"
        );
        before = after;
    }
}
