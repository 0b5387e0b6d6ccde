//! The global order of control points, from which the layout places every
//! unknown (IV.A): rods that no constraint links keep their natural order;
//! linked rods (a duplex's two strands, a ladder's rails, a fabric's
//! courses) and closed rods are ordered by reverse Cuthill–McKee on the
//! graph of control points (neighbours along a rod, and across every
//! two-rod constraint), which keeps the band narrow whatever direction the
//! rods run in. A user interleave group (`World::interleave`) keeps the
//! thesis' merge by relative position along each rod.
use std::collections::VecDeque;

/// What the ordering needs of a rod: its control points and the control
/// points of each segment (a closed rod's last segments wrap around).
pub struct RodGraph<'a> {
    pub n_ctrl: usize,
    pub segments: &'a [[usize; 4]],
}

/// A link between control point `ca` of rod `a` and `cb` of rod `b`.
pub type Link = (usize, usize, usize, usize);

/// How linked rods are ordered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Reverse Cuthill–McKee on the control-point graph.
    Rcm,
    /// Merge by relative position along each rod, each rod oriented by its
    /// links to the component's first rod (antiparallel rods reversed).
    Parameter,
}

/// Every (rod, control point) once, in the global order (reverse
/// Cuthill–McKee for linked rods).
pub fn control_point_order(rods: &[RodGraph<'_>], links: &[Link], groups: &[Vec<usize>]) -> Vec<(usize, usize)> {
    control_point_order_with(rods, links, groups, Strategy::Rcm)
}

/// The same with a chosen strategy for linked rods; the layout tries both
/// and keeps the narrower band.
pub fn control_point_order_with(rods: &[RodGraph<'_>], links: &[Link], groups: &[Vec<usize>], strategy: Strategy) -> Vec<(usize, usize)> {
    let nr = rods.len();
    // Components of rods linked by constraints or grouped by the user.
    let mut parent: Vec<usize> = (0..nr).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let union = |p: &mut Vec<usize>, a: usize, b: usize| {
        let (ra, rb) = (find(p, a), find(p, b));
        if ra != rb {
            p[ra.max(rb)] = ra.min(rb);
        }
    };
    for &(a, _, b, _) in links {
        if a != b && a < nr && b < nr {
            union(&mut parent, a, b);
        }
    }
    for g in groups {
        for w in g.windows(2) {
            if w[0] < nr && w[1] < nr {
                union(&mut parent, w[0], w[1]);
            }
        }
    }
    let roots: Vec<usize> = (0..nr).map(|r| find(&mut parent, r)).collect();
    let mut group_of = vec![usize::MAX; nr];
    for (g, members) in groups.iter().enumerate() {
        for &r in members {
            if r < nr {
                group_of[r] = g;
            }
        }
    }
    let mut order = Vec::with_capacity(rods.iter().map(|r| r.n_ctrl).sum());
    // Rods of each component, in rod order.
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); nr];
    for r in 0..nr {
        members[roots[r]].push(r);
    }
    for r in 0..nr {
        if roots[r] != r {
            continue; // each component once, at its smallest rod (its root)
        }
        let comp = std::mem::take(&mut members[r]);
        let user_groups: Vec<usize> = {
            let mut g: Vec<usize> = comp.iter().filter_map(|&q| (group_of[q] != usize::MAX).then_some(group_of[q])).collect();
            g.sort_unstable();
            g.dedup();
            g
        };
        if !user_groups.is_empty() {
            // The user's merge by relative position, then the other rods in turn.
            let mut placed = vec![false; nr];
            for g in user_groups {
                merge_by_parameter(rods, &groups[g], &mut order);
                groups[g].iter().filter(|&&q| q < nr).for_each(|&q| placed[q] = true);
            }
            for &q in &comp {
                if !placed[q] {
                    order.extend((0..rods[q].n_ctrl).map(|i| (q, i)));
                }
            }
        } else if comp.len() == 1 && !wraps(&rods[r]) {
            order.extend((0..rods[r].n_ctrl).map(|i| (r, i)));
        } else if strategy == Strategy::Parameter && comp.len() > 1 {
            merge_oriented(rods, &comp, links, &mut order);
        } else {
            reverse_cuthill_mckee(rods, &comp, links, &mut order);
        }
    }
    order
}

/// Merge by relative position, each rod of `comp` reversed when its links
/// to already oriented rods run the other way (a negative correlation of
/// the linked control-point positions).
fn merge_oriented(rods: &[RodGraph<'_>], comp: &[usize], links: &[Link], order: &mut Vec<(usize, usize)>) {
    let frac = |q: usize, i: usize| i as f64 / (rods[q].n_ctrl.max(2) - 1) as f64;
    let mut reversed: Vec<Option<bool>> = vec![None; rods.len()];
    // Links by rod, then a breadth-first walk from the first rod: each rod
    // is oriented by its links to the rods oriented before it. O(links).
    let mut by_rod: Vec<Vec<usize>> = vec![Vec::new(); rods.len()];
    for (k, &(a, _, b, _)) in links.iter().enumerate() {
        if a != b && a < rods.len() && b < rods.len() {
            by_rod[a].push(k);
            by_rod[b].push(k);
        }
    }
    let mut queue = VecDeque::new();
    for &root in comp {
        if reversed[root].is_some() {
            continue;
        }
        reversed[root] = Some(false);
        queue.push_back(root);
        while let Some(other) = queue.pop_front() {
            // Neighbours of `other` not oriented yet, each from all its links
            // to oriented rods.
            let next: Vec<usize> = by_rod[other]
                .iter()
                .map(|&k| if links[k].0 == other { links[k].2 } else { links[k].0 })
                .filter(|&q| reversed[q].is_none())
                .collect();
            for q in next {
                if reversed[q].is_some() {
                    continue;
                }
                let (mut sxy, mut sx, mut sy, mut sxx, mut syy, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
                for &k in &by_rod[q] {
                    let (a, ca, b, cb) = links[k];
                    let (mine, o, theirs) = if a == q { (ca, b, cb) } else { (cb, a, ca) };
                    let Some(rev) = reversed[o] else { continue };
                    let x = frac(q, mine);
                    let y = if rev { frac(o, rods[o].n_ctrl - 1 - theirs) } else { frac(o, theirs) };
                    sxy += x * y;
                    sx += x;
                    sy += y;
                    sxx += x * x;
                    syy += y * y;
                    n += 1.0;
                }
                let cov = sxy / n - sx * sy / (n * n);
                let var = (sxx / n - sx * sx / (n * n)) * (syy / n - sy * sy / (n * n));
                reversed[q] = Some(var > 0.0 && cov < 0.0);
                queue.push_back(q);
            }
        }
    }
    let mut merged: Vec<(f64, usize, usize)> = comp
        .iter()
        .flat_map(|&q| {
            let rev = reversed[q].unwrap_or(false);
            let n = rods[q].n_ctrl;
            // Mirror the index, not the fraction, so equal positions tie exactly.
            (0..n).map(move |i| (if rev { frac(q, n - 1 - i) } else { frac(q, i) }, q, i))
        })
        .collect();
    merged.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    order.extend(merged.into_iter().map(|(_, q, i)| (q, i)));
}

/// A closed rod: some segment uses control points that are not consecutive.
fn wraps(rod: &RodGraph<'_>) -> bool {
    rod.segments.iter().any(|c| c.windows(2).any(|w| w[1] != w[0] + 1))
}

fn merge_by_parameter(rods: &[RodGraph<'_>], group: &[usize], order: &mut Vec<(usize, usize)>) {
    let mut merged: Vec<(f64, usize, usize)> = group
        .iter()
        .filter(|&&q| q < rods.len())
        .flat_map(|&q| {
            let n = rods[q].n_ctrl;
            (0..n).map(move |i| (i as f64 / (n.max(2) - 1) as f64, q, i))
        })
        .collect();
    merged.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    order.extend(merged.into_iter().map(|(_, q, i)| (q, i)));
}

/// Reverse Cuthill–McKee on the control points of the rods `comp`, from a
/// pseudo-peripheral node (George–Liu).
fn reverse_cuthill_mckee(rods: &[RodGraph<'_>], comp: &[usize], links: &[Link], order: &mut Vec<(usize, usize)>) {
    // Node numbering within the component.
    let mut first = vec![usize::MAX; rods.len()];
    let mut n = 0;
    for &q in comp {
        first[q] = n;
        n += rods[q].n_ctrl;
    }
    let node = |q: usize, i: usize| first[q] + i;
    let mut edges: Vec<(usize, usize)> = Vec::new();
    for &q in comp {
        for seg in rods[q].segments {
            for w in seg.windows(2) {
                if w[0] != w[1] {
                    edges.push((node(q, w[0]), node(q, w[1])));
                }
            }
        }
    }
    for &(a, ca, b, cb) in links {
        if a < rods.len() && b < rods.len() && first[a] != usize::MAX && first[b] != usize::MAX && ca < rods[a].n_ctrl && cb < rods[b].n_ctrl {
            let (x, y) = (node(a, ca), node(b, cb));
            if x != y {
                edges.push((x, y));
            }
        }
    }
    // Compressed adjacency, duplicates removed.
    let mut deg = vec![0usize; n + 1];
    for &(x, y) in &edges {
        deg[x] += 1;
        deg[y] += 1;
    }
    let mut start = vec![0usize; n + 1];
    for i in 0..n {
        start[i + 1] = start[i] + deg[i];
    }
    let mut fill = start.clone();
    let mut adj = vec![0usize; start[n]];
    for &(x, y) in &edges {
        adj[fill[x]] = y;
        fill[x] += 1;
        adj[fill[y]] = x;
        fill[y] += 1;
    }
    let mut degree = vec![0usize; n];
    for i in 0..n {
        let s = &mut adj[start[i]..start[i + 1]];
        s.sort_unstable();
        let mut m = 0;
        for k in 0..s.len() {
            if k == 0 || s[k] != s[k - 1] {
                s[m] = s[k];
                m += 1;
            }
        }
        degree[i] = m;
    }
    let nbrs = |i: usize| &adj[start[i]..start[i] + degree[i]];
    let mut level = vec![usize::MAX; n];
    let mut queue = VecDeque::new();
    // BFS levels from `s` over unvisited nodes; returns the last level.
    let mut bfs = |s: usize, level: &mut Vec<usize>| -> (usize, Vec<usize>) {
        level.iter_mut().for_each(|l| *l = usize::MAX);
        level[s] = 0;
        queue.clear();
        queue.push_back(s);
        let mut last = (0, vec![s]);
        while let Some(x) = queue.pop_front() {
            for &y in nbrs(x) {
                if level[y] == usize::MAX {
                    level[y] = level[x] + 1;
                    if level[y] > last.0 {
                        last = (level[y], Vec::new());
                    }
                    last.1.push(y);
                    queue.push_back(y);
                }
            }
        }
        last
    };
    let mut visited = vec![false; n];
    let mut cm: Vec<usize> = Vec::with_capacity(n);
    let mut next_root = 0;
    while cm.len() < n {
        while visited[next_root] {
            next_root += 1;
        }
        // Pseudo-peripheral start: move to a least-degree node of the last
        // level while the eccentricity grows.
        let mut s = next_root;
        let mut ecc = bfs(s, &mut level);
        for _ in 0..8 {
            let cand = ecc.1.iter().copied().filter(|&x| !visited[x]).min_by_key(|&x| (degree[x], x)).unwrap_or(s);
            let e = bfs(cand, &mut level);
            if e.0 <= ecc.0 {
                break;
            }
            s = cand;
            ecc = e;
        }
        // Cuthill–McKee from s.
        let begin = cm.len();
        visited[s] = true;
        cm.push(s);
        let mut head = begin;
        let mut buf: Vec<usize> = Vec::new();
        while head < cm.len() {
            let x = cm[head];
            head += 1;
            buf.clear();
            buf.extend(nbrs(x).iter().copied().filter(|&y| !visited[y]));
            buf.sort_by_key(|&y| (degree[y], y));
            for &y in &buf {
                visited[y] = true;
                cm.push(y);
            }
        }
    }
    cm.reverse();
    let mut owner: Vec<(usize, usize)> = Vec::with_capacity(n);
    for &q in comp {
        owner.extend((0..rods[q].n_ctrl).map(|i| (q, i)));
    }
    order.extend(cm.into_iter().map(|x| owner[x]));
}

#[cfg(test)]
mod tests {
    use super::*;
    fn chain(n: usize) -> Vec<[usize; 4]> {
        (0..n - 3).map(|s| [s, s + 1, s + 2, s + 3]).collect()
    }
    fn ring(n: usize) -> Vec<[usize; 4]> {
        (0..n).map(|s| [s, (s + 1) % n, (s + 2) % n, (s + 3) % n]).collect()
    }
    /// Largest distance in the order between two control points of a segment
    /// or of a link.
    fn spread(order: &[(usize, usize)], rods: &[RodGraph<'_>], links: &[Link]) -> usize {
        let mut rank = vec![vec![0; 0]; rods.len()];
        for (r, g) in rods.iter().enumerate() {
            rank[r] = vec![0; g.n_ctrl];
        }
        for (k, &(r, i)) in order.iter().enumerate() {
            rank[r][i] = k;
        }
        let mut m = 0;
        for (r, g) in rods.iter().enumerate() {
            for s in g.segments {
                let (lo, hi) = s.iter().fold((usize::MAX, 0), |(lo, hi), &c| (lo.min(rank[r][c]), hi.max(rank[r][c])));
                m = m.max(hi - lo);
            }
        }
        for &(a, ca, b, cb) in links {
            m = m.max(rank[a][ca].abs_diff(rank[b][cb]));
        }
        m
    }
    #[test]
    fn single_open_rod_keeps_its_order() {
        let s = chain(10);
        let o = control_point_order(&[RodGraph { n_ctrl: 10, segments: &s }], &[], &[]);
        assert_eq!(o, (0..10).map(|i| (0, i)).collect::<Vec<_>>());
    }
    /// A ring's wrap-around no longer spans the whole rod.
    #[test]
    fn ring_band_is_local() {
        let s = ring(200);
        let rods = [RodGraph { n_ctrl: 200, segments: &s }];
        let o = control_point_order(&rods, &[], &[]);
        assert_eq!(o.len(), 200);
        assert!(spread(&o, &rods, &[]) <= 6, "spread {}", spread(&o, &rods, &[]));
    }
    /// Antiparallel strands linked rung by rung get the same narrow band as
    /// parallel ones, whatever the insertion order.
    #[test]
    fn antiparallel_strands_interleave() {
        let n = 300;
        let s = chain(n);
        let rods = [RodGraph { n_ctrl: n, segments: &s }, RodGraph { n_ctrl: n, segments: &s }];
        let anti: Vec<Link> = (0..n).map(|i| (0, i, 1, n - 1 - i)).collect();
        let par: Vec<Link> = (0..n).map(|i| (0, i, 1, i)).collect();
        let (oa, op) = (control_point_order(&rods, &anti, &[]), control_point_order(&rods, &par, &[]));
        let (sa, sp) = (spread(&oa, &rods, &anti), spread(&op, &rods, &par));
        assert!(sa <= 8 && sp <= 8, "antiparallel {sa}, parallel {sp}");
        // Merged by parameter, the antiparallel rod is reversed: same spread.
        let (ma, mp) = (
            control_point_order_with(&rods, &anti, &[], Strategy::Parameter),
            control_point_order_with(&rods, &par, &[], Strategy::Parameter),
        );
        let (sa, sp) = (spread(&ma, &rods, &anti), spread(&mp, &rods, &par));
        assert_eq!(sa, sp, "merged: antiparallel {sa}, parallel {sp}");
        assert!(sp <= 6, "merged spread {sp}");
    }
}
