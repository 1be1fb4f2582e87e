//! Raw links to compressed link groups (the paper's compression, on the CPU): each element's
//! rays, in ray order, become one group of (peer, weight) pairs with the links to one peer
//! summed, the peers in the order their first link appeared. The groups of all elements form
//! one array indexed by offsets (CSR). Ray order fixes the order of every sum, so the groups
//! are the same bits whichever devices shot which rays.

/// What one ray of an element found: the hit triangle's three corners as elements, weighted by
/// the hit's barycentrics (they sum to one). A miss, a back face or no triangle: `None`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    pub corners: [u32; 3],
    pub barycentrics: [f32; 3],
}

/// The compressed links of every element: element x's are `peers[offsets[x]..offsets[x + 1]]`
/// with `weights` alike; w_xy = (1 / n_C) * the sum of y's barycentrics over x's rays that hit a
/// triangle with corner y.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinkGroups {
    pub offsets: Vec<u32>,
    pub peers: Vec<u32>,
    pub weights: Vec<f32>,
    /// Links before compression (one per corner of each hit with a nonzero barycentric).
    pub raw_links: u64,
    /// Of those, each element's (what splicing a group in its place subtracts).
    pub raw_of: Vec<u32>,
}

impl LinkGroups {
    /// The groups of `hits.len() / rays` elements from their rays' hits, element after element,
    /// each element's `rays` in ray order.
    pub fn from_hits(rays: u32, hits: &[Option<RayHit>]) -> LinkGroups {
        assert!(rays > 0 && hits.len().is_multiple_of(rays as usize));
        let mut groups = LinkGroups {
            offsets: vec![0],
            ..Default::default()
        };
        // Sums in f64 in ray order, rounded once per link; `at` finds a peer's sum (a hash
        // map rather than a scan: fine meshes give an element over a thousand peers).
        let mut sums: Vec<(u32, f64)> = Vec::new();
        let mut at: std::collections::HashMap<u32, usize> = std::collections::HashMap::new();
        for element in hits.chunks(rays as usize) {
            sums.clear();
            at.clear();
            let mut raw = 0;
            for hit in element.iter().flatten() {
                for (&peer, &b) in hit.corners.iter().zip(&hit.barycentrics) {
                    if b == 0.0 {
                        continue;
                    }
                    raw += 1;
                    match at.entry(peer) {
                        std::collections::hash_map::Entry::Occupied(e) => {
                            sums[*e.get()].1 += b as f64
                        }
                        std::collections::hash_map::Entry::Vacant(e) => {
                            e.insert(sums.len());
                            sums.push((peer, b as f64));
                        }
                    }
                }
            }
            for &(peer, sum) in &sums {
                groups.peers.push(peer);
                groups.weights.push((sum / rays as f64) as f32);
            }
            groups.offsets.push(groups.peers.len() as u32);
            groups.raw_links += raw as u64;
            groups.raw_of.push(raw);
        }
        groups
    }

    pub fn elements(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Element x's links: (peer, weight) in group order.
    pub fn group(&self, x: usize) -> impl Iterator<Item = (u32, f32)> + '_ {
        let range = self.offsets[x] as usize..self.offsets[x + 1] as usize;
        self.peers[range.clone()]
            .iter()
            .copied()
            .zip(self.weights[range].iter().copied())
    }

    /// Appends the groups of the elements that follow these (a later batch's).
    pub fn append(&mut self, next: LinkGroups) {
        let base = self.peers.len() as u32;
        self.offsets
            .extend(next.offsets[1..].iter().map(|&o| o + base));
        self.peers.extend(next.peers);
        self.weights.extend(next.weights);
        self.raw_links += next.raw_links;
        self.raw_of.extend(next.raw_of);
    }

    /// These groups with those of the `changed` elements (ascending, each with its one new
    /// group) in their place: the groups a reduction of every element's hits would give, when
    /// the others' hits are the same.
    pub fn spliced(&self, changed: &[(usize, LinkGroups)]) -> LinkGroups {
        let mut out = LinkGroups {
            offsets: vec![0],
            ..Default::default()
        };
        out.peers.reserve(self.peers.len());
        out.weights.reserve(self.weights.len());
        let mut next = changed.iter().peekable();
        for x in 0..self.elements() {
            let (group, raw) = match next.next_if(|(c, _)| *c == x) {
                Some((_, g)) => {
                    assert_eq!(g.elements(), 1, "a spliced group is one element's");
                    (g.peers.iter().zip(&g.weights), g.raw_of[0])
                }
                None => {
                    let range = self.offsets[x] as usize..self.offsets[x + 1] as usize;
                    (
                        self.peers[range.clone()].iter().zip(&self.weights[range]),
                        self.raw_of[x],
                    )
                }
            };
            for (&p, &w) in group {
                out.peers.push(p);
                out.weights.push(w);
            }
            out.offsets.push(out.peers.len() as u32);
            out.raw_of.push(raw);
            out.raw_links += raw as u64;
        }
        assert!(
            next.next().is_none(),
            "changed groups past the last element"
        );
        out
    }

    /// Bytes of the compressed groups (offsets, peers, weights).
    pub fn bytes(&self) -> usize {
        4 * (self.offsets.len() + self.peers.len() + self.weights.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(corners: [u32; 3], barycentrics: [f32; 3]) -> Option<RayHit> {
        Some(RayHit {
            corners,
            barycentrics,
        })
    }

    #[test]
    fn links_to_one_peer_are_summed_in_order_of_first_appearance() {
        // Element 0: four rays, one a miss; element 1: two hits of one triangle.
        let hits = [
            hit([3, 4, 5], [0.5, 0.25, 0.25]),
            None,
            hit([5, 6, 3], [0.5, 0.5, 0.0]),
            hit([4, 3, 7], [1.0, 0.0, 0.0]),
            hit([2, 0, 9], [0.25, 0.25, 0.5]),
            hit([2, 0, 9], [0.25, 0.25, 0.5]),
            None,
            None,
        ];
        let g = LinkGroups::from_hits(4, &hits);
        assert_eq!(g.offsets, [0, 4, 7]);
        assert_eq!(g.peers, [3, 4, 5, 6, 2, 0, 9]);
        assert_eq!(
            g.weights,
            [0.125, 0.3125, 0.1875, 0.125, 0.125, 0.125, 0.25]
        );
        assert_eq!(g.raw_links, 6 + 6);
        assert_eq!(g.raw_of, [6, 6]);
        // An element's weights sum to the fraction of its rays that hit.
        let sum = |x| g.group(x).map(|l| l.1).sum::<f32>();
        assert_eq!((sum(0), sum(1)), (0.75, 0.5));
        assert_eq!(g.bytes(), 4 * (3 + 7 + 7));
    }

    #[test]
    fn splicing_a_group_gives_what_reducing_every_element_gives() {
        let before = [
            hit([3, 4, 5], [0.5, 0.25, 0.25]),
            None,
            hit([1, 2, 0], [1.0, 0.0, 0.0]),
            None,
            None,
            hit([0, 1, 2], [0.5, 0.5, 0.0]),
        ];
        let mut after = before;
        after[2] = hit([6, 7, 8], [0.25, 0.25, 0.5]);
        after[3] = hit([6, 1, 0], [0.5, 0.25, 0.25]);
        let old = LinkGroups::from_hits(2, &before);
        let spliced = old.spliced(&[(1, LinkGroups::from_hits(2, &after[2..4]))]);
        assert_eq!(spliced, LinkGroups::from_hits(2, &after));
        assert_eq!(old.spliced(&[]), old);
    }

    #[test]
    fn an_element_whose_rays_all_miss_has_an_empty_group() {
        let g = LinkGroups::from_hits(2, &[None, None, hit([0, 1, 2], [1.0, 0.0, 0.0]), None]);
        assert_eq!(g.elements(), 2);
        assert_eq!(g.group(0).count(), 0);
        assert_eq!(g.group(1).collect::<Vec<_>>(), [(0, 0.5)]);
    }
}
