//! The stroke graph: the skeleton's end points and junctions (nodes) and the pixel paths
//! between them (edges); spurs pruned, nearby junctions joined, and edges paired through
//! junctions into strokes.

use super::skeleton::{Grid, RING};
use crate::geom::{angle_between, Point};

/// A skeleton node: an end point (one edge) or a junction (three or more).
#[derive(Clone, Debug)]
pub(crate) struct Node {
    /// The mean of its pixels' centres (px).
    pub(crate) centre: Point,
    /// Distance from the centre to the boundary (px).
    pub(crate) radius: f64,
    pub(crate) alive: bool,
    /// Where the node is the sharp corner of one stroke (the tip of a V): the corner's
    /// point, where the two arms' lines meet.
    pub(crate) corner: Option<Point>,
}

/// A path of skeleton points between two nodes, or a closed loop (`ends: None`).
#[derive(Clone, Debug)]
pub(crate) struct Edge {
    pub(crate) ends: Option<[usize; 2]>,
    /// Centres along the path, nodes' pixels included at both ends.
    pub(crate) points: Vec<Point>,
    /// The stroke's radius at each point.
    pub(crate) radii: Vec<f64>,
    pub(crate) alive: bool,
}

/// The skeleton as nodes and edges.
#[derive(Clone, Debug, Default)]
pub(crate) struct Graph {
    pub(crate) nodes: Vec<Node>,
    pub(crate) edges: Vec<Edge>,
    /// Nodes with no edge at all: a dot (a one-pixel skeleton).
    pub(crate) dots: Vec<usize>,
}

fn centre_of(i: usize, width: usize) -> Point {
    Point::new((i % width) as f64 + 0.5, (i / width) as f64 + 0.5)
}

/// Builds the graph of a thinned grid (pixel centres, radii not yet known: NaN).
pub(crate) fn build(grid: &Grid) -> Graph {
    let w = grid.width;
    let at = |i: usize| ((i % w) as isize, (i / w) as isize);
    let index = |x: isize, y: isize| y as usize * w + x as usize;
    let set: Vec<usize> = (0..grid.cells.len()).filter(|&i| grid.cells[i]).collect();
    let mut node_of = vec![usize::MAX; grid.cells.len()];
    let is_node = |i: usize| {
        let (x, y) = at(i);
        grid.neighbours(x, y) != 2
    };
    let mut graph = Graph::default();
    // Node pixels, grouped 8-connected into nodes.
    for &start in &set {
        if node_of[start] != usize::MAX || !is_node(start) {
            continue;
        }
        let id = graph.nodes.len();
        let mut stack = vec![start];
        node_of[start] = id;
        let (mut sum, mut count) = (Point::new(0.0, 0.0), 0.0);
        while let Some(i) = stack.pop() {
            sum += centre_of(i, w);
            count += 1.0;
            let (x, y) = at(i);
            for (dx, dy) in RING {
                if grid.get(x + dx, y + dy) {
                    let j = index(x + dx, y + dy);
                    if node_of[j] == usize::MAX && is_node(j) {
                        node_of[j] = id;
                        stack.push(j);
                    }
                }
            }
        }
        graph.nodes.push(Node {
            centre: sum * (1.0 / count),
            radius: f64::NAN,
            alive: true,
            corner: None,
        });
    }
    let mut visited = vec![false; grid.cells.len()];
    let next_of = |cur: usize, prev: usize| -> Option<usize> {
        let (x, y) = at(cur);
        RING.iter()
            .filter(|&&(dx, dy)| grid.get(x + dx, y + dy))
            .map(|&(dx, dy)| index(x + dx, y + dy))
            .find(|&j| j != prev)
    };
    let mut has_edge = vec![false; graph.nodes.len()];
    for &u in &set {
        if node_of[u] == usize::MAX {
            continue;
        }
        let (x, y) = at(u);
        for (dx, dy) in RING {
            if !grid.get(x + dx, y + dy) {
                continue;
            }
            let v = index(x + dx, y + dy);
            if node_of[v] != usize::MAX || visited[v] {
                continue;
            }
            let mut pixels = vec![u, v];
            visited[v] = true;
            let (mut prev, mut cur) = (u, v);
            let end = loop {
                let Some(next) = next_of(cur, prev) else {
                    break None;
                };
                pixels.push(next);
                if node_of[next] != usize::MAX {
                    break Some(node_of[next]);
                }
                if visited[next] {
                    break None;
                }
                visited[next] = true;
                (prev, cur) = (cur, next);
            };
            let Some(end) = end else { continue };
            has_edge[node_of[u]] = true;
            has_edge[end] = true;
            graph.edges.push(Edge {
                ends: Some([node_of[u], end]),
                radii: vec![f64::NAN; pixels.len()],
                points: pixels.iter().map(|&i| centre_of(i, w)).collect(),
                alive: true,
            });
        }
    }
    // Loops of path pixels that touch no node.
    for &s in &set {
        if node_of[s] != usize::MAX || visited[s] {
            continue;
        }
        let mut pixels = vec![s];
        visited[s] = true;
        let (mut prev, mut cur) = (usize::MAX, s);
        while let Some(next) = next_of(cur, prev) {
            if visited[next] {
                break;
            }
            visited[next] = true;
            pixels.push(next);
            (prev, cur) = (cur, next);
        }
        graph.edges.push(Edge {
            ends: None,
            radii: vec![f64::NAN; pixels.len()],
            points: pixels.iter().map(|&i| centre_of(i, w)).collect(),
            alive: true,
        });
    }
    graph.dots = (0..graph.nodes.len()).filter(|&n| !has_edge[n]).collect();
    graph
}

impl Graph {
    /// The number of edge ends at each node (a loop through one node counts twice).
    pub(crate) fn degrees(&self) -> Vec<usize> {
        let mut d = vec![0; self.nodes.len()];
        for e in self.edges.iter().filter(|e| e.alive) {
            if let Some([a, b]) = e.ends {
                d[a] += 1;
                d[b] += 1;
            }
        }
        d
    }

    /// Removes spurs, shortest first: an edge from an end point to a junction whose disks
    /// reach less than `limit` px beyond the junction's disk (`max |p − c| + r − r_j`).
    /// Such a branch describes a bump of the boundary no higher than `limit`, not a
    /// stroke. Returns how many were removed.
    pub(crate) fn prune_spurs(&mut self, limit: f64) -> usize {
        let mut removed = 0;
        loop {
            let degree = self.degrees();
            let mut best: Option<(f64, usize)> = None;
            for (k, e) in self.edges.iter().enumerate() {
                let Some([a, b]) = e.ends else { continue };
                if !e.alive || a == b {
                    continue;
                }
                let junction = match (degree[a], degree[b]) {
                    (1, d) if d >= 3 => b,
                    (d, 1) if d >= 3 => a,
                    _ => continue,
                };
                let j = &self.nodes[junction];
                let reach = e
                    .points
                    .iter()
                    .zip(&e.radii)
                    .map(|(p, r)| p.distance(j.centre) + r)
                    .fold(f64::NEG_INFINITY, f64::max)
                    - j.radius;
                if reach < limit && best.is_none_or(|(b, _)| reach < b) {
                    best = Some((reach, k));
                }
            }
            let Some((_, k)) = best else { break };
            let e = &mut self.edges[k];
            e.alive = false;
            if let Some([a, b]) = e.ends {
                let end = if degree[a] == 1 { a } else { b };
                self.nodes[end].alive = false;
            }
            removed += 1;
        }
        removed
    }

    /// Joins two junctions whose centres are closer than the sum of their radii plus two
    /// pixels (their disks overlap, up to the skeleton's pixel steps): thinning splits a
    /// crossing of two strokes into two forks joined by a short edge.
    pub(crate) fn join_close_junctions(&mut self) {
        loop {
            let degree = self.degrees();
            let found = self.edges.iter().position(|e| {
                let Some([a, b]) = e.ends else { return false };
                let (na, nb) = (&self.nodes[a], &self.nodes[b]);
                e.alive
                    && a != b
                    && degree[a] >= 3
                    && degree[b] >= 3
                    && na.centre.distance(nb.centre) <= na.radius + nb.radius + 2.0
            });
            let Some(k) = found else { break };
            let [a, b] = self.edges[k].ends.unwrap_or([0, 0]);
            self.edges[k].alive = false;
            let (ca, cb) = (self.nodes[a].centre, self.nodes[b].centre);
            self.nodes[a].centre = ca.lerp(cb, 0.5);
            self.nodes[a].radius = self.nodes[a].radius.max(self.nodes[b].radius);
            self.nodes[b].alive = false;
            for e in &mut self.edges {
                if let Some(ends) = &mut e.ends {
                    for end in ends.iter_mut().filter(|n| **n == b) {
                        *end = a;
                    }
                }
            }
        }
    }

    /// Joins the two edges at every node of degree 2 into one (a loop when both are the
    /// same edge).
    pub(crate) fn join_through_degree_two(&mut self) {
        loop {
            let degree = self.degrees();
            let Some(n) = (0..self.nodes.len()).find(|&n| self.nodes[n].alive && degree[n] == 2)
            else {
                break;
            };
            self.nodes[n].alive = false;
            let at: Vec<usize> = (0..self.edges.len())
                .filter(|&k| {
                    self.edges[k].alive && self.edges[k].ends.is_some_and(|e| e.contains(&n))
                })
                .collect();
            if at.len() == 1 {
                // A loop from the node back to itself.
                self.edges[at[0]].ends = None;
                continue;
            }
            let (first, second) = (at[0], at[1]);
            let mut a = self.edges[first].clone();
            let mut b = self.edges[second].clone();
            // Orient a to end at n and b to start at n.
            if a.ends.is_some_and(|e| e[0] == n) {
                a.reverse();
            }
            if b.ends.is_some_and(|e| e[1] == n) {
                b.reverse();
            }
            let (ea, eb) = (a.ends.unwrap_or([n, n]), b.ends.unwrap_or([n, n]));
            if let Some(x) = self.nodes[n].corner {
                // The sharp corner: the arms' points inside the node's disk give way to
                // the corner point.
                let node = &self.nodes[n];
                let inside = |p: &Point| p.distance(node.centre) <= node.radius;
                while a.points.len() > 1 && inside(&a.points[a.points.len() - 1]) {
                    a.points.pop();
                    a.radii.pop();
                }
                let skip = b.points.iter().take_while(|p| inside(p)).count();
                let skip = skip.min(b.points.len() - 1);
                b.points.drain(..skip);
                b.radii.drain(..skip);
                let r = (a.radii[a.radii.len() - 1] + b.radii[0]) / 2.0;
                a.points.push(x);
                a.radii.push(r);
                a.points.extend_from_slice(&b.points);
                a.radii.extend_from_slice(&b.radii);
            } else {
                a.points.extend_from_slice(&b.points[1..]);
                a.radii.extend_from_slice(&b.radii[1..]);
            }
            a.ends = Some([ea[0], eb[1]]);
            self.edges[first] = a;
            self.edges[second].alive = false;
        }
    }

    /// The direction in which edge `k` leaves its node at end `end` (0 or 1).
    pub(crate) fn leaving_direction(&self, k: usize, end: usize) -> Point {
        self.leaving(k, end).1
    }

    /// Where edge `k` leaves its node at end `end` (0 or 1), and in which direction: from
    /// where it leaves the node's disk to a point `max(8, 3 r)` px further along.
    pub(crate) fn leaving(&self, k: usize, end: usize) -> (Point, Point) {
        let node = &self.nodes[self.edges[k].ends.map_or(0, |e| e[end])];
        let pts = &self.edges[k].points;
        let ordered: Vec<Point> = if end == 0 {
            pts.clone()
        } else {
            pts.iter().rev().copied().collect()
        };
        let from = ordered
            .iter()
            .position(|p| p.distance(node.centre) > node.radius)
            .unwrap_or(ordered.len() - 1);
        let span = (3.0 * node.radius).max(8.0);
        let mut s = 0.0;
        let mut to = from;
        while to + 1 < ordered.len() && s < span {
            s += ordered[to].distance(ordered[to + 1]);
            to += 1;
        }
        let start = if to == from {
            node.centre
        } else {
            ordered[from]
        };
        let dir = (ordered[to] - start)
            .normalized()
            .unwrap_or(Point::new(1.0, 0.0));
        (start, dir)
    }

    /// Finds the tips of sharp corners: thinning turns the corner of a V into a junction
    /// with a short branch to the tip. A junction of three branches is a corner when one
    /// branch ends freely and every point of it outside the junction's disk lies, with
    /// its disk, within the strokes of the two other branches continued straight to where their lines
    /// meet (the corner point), up to `tolerance`. That branch is removed and the junction
    /// becomes the corner of one stroke. Returns how many were found.
    pub(crate) fn absorb_corner_tips(&mut self, tolerance: f64) -> usize {
        let mut found = 0;
        let degree = self.degrees();
        for n in 0..self.nodes.len() {
            if !self.nodes[n].alive || degree[n] != 3 {
                continue;
            }
            let at: Vec<EdgeEnd> = (0..self.edges.len())
                .filter(|&k| self.edges[k].alive)
                .flat_map(|k| {
                    let ends = self.edges[k].ends;
                    (0..2).filter_map(move |e| {
                        ends.filter(|x| x[e] == n && x[0] != x[1]).map(|_| (k, e))
                    })
                })
                .collect();
            if at.len() != 3 {
                continue;
            }
            for s in 0..3 {
                let (ks, es) = at[s];
                let Some(ends) = self.edges[ks].ends else {
                    continue;
                };
                if degree[ends[1 - es]] != 1 {
                    continue;
                }
                let (a, b) = (at[(s + 1) % 3], at[(s + 2) % 3]);
                let (pa, da) = self.leaving(a.0, a.1);
                let (pb, db) = self.leaving(b.0, b.1);
                // Lines pa − da·u and pb − db·v, meeting behind both anchors.
                let den = da.cross(db);
                if den.abs() < 0.2 {
                    continue; // nearly parallel arms: a T, not a V
                }
                let q = pb - pa;
                let u = -q.cross(db) / den;
                let v = -q.cross(da) / den;
                if u <= 0.0 || v <= 0.0 {
                    continue;
                }
                let x = pa - da * u;
                let arm_radius = {
                    let r = |k: usize, e: usize| {
                        let radii = &self.edges[k].radii;
                        let m = radii.len();
                        let take = m.min(8);
                        let it: Vec<f64> = if e == 0 {
                            radii[m / 4..(m / 4 + take).min(m)].to_vec()
                        } else {
                            radii[(m - m / 4).saturating_sub(take)..m - m / 4].to_vec()
                        };
                        it.iter().sum::<f64>() / it.len().max(1) as f64
                    };
                    (r(a.0, a.1) + r(b.0, b.1)) / 2.0
                };
                let node = &self.nodes[n];
                let spur = &self.edges[ks];
                // A disk lies within the arms' strokes when its circle does (sampled).
                let within = |q: Point| {
                    crate::geom::segment_distance(q, pa, x)
                        .min(crate::geom::segment_distance(q, x, pb))
                        <= arm_radius + tolerance
                };
                let covered = spur.points.iter().zip(&spur.radii).all(|(p, r)| {
                    p.distance(node.centre) <= node.radius
                        || (0..16).all(|k| {
                            let a = k as f64 * std::f64::consts::PI / 8.0;
                            within(*p + Point::new(a.cos(), a.sin()) * *r)
                        })
                });
                if covered {
                    self.edges[ks].alive = false;
                    self.nodes[ends[1 - es]].alive = false;
                    self.nodes[n].corner = Some(x);
                    found += 1;
                    break;
                }
            }
        }
        found
    }
}

impl Edge {
    pub(crate) fn reverse(&mut self) {
        self.points.reverse();
        self.radii.reverse();
        if let Some(e) = &mut self.ends {
            e.swap(0, 1);
        }
    }
}

/// One edge end at a node: (edge, which end).
pub(crate) type EdgeEnd = (usize, usize);

/// At every junction, pairs the edge ends that continue each other: greedily the pair
/// that turns least, as long as it turns by at most `max_turn` radians. Returns, for every
/// edge end, the end it continues into.
pub(crate) fn pair_at_junctions(graph: &Graph, max_turn: f64) -> Vec<[Option<EdgeEnd>; 2]> {
    let mut link = vec![[None, None]; graph.edges.len()];
    let degree = graph.degrees();
    for n in (0..graph.nodes.len()).filter(|&n| graph.nodes[n].alive && degree[n] >= 3) {
        let mut ends: Vec<(EdgeEnd, Point)> = Vec::new();
        for (k, e) in graph.edges.iter().enumerate() {
            let Some(pair) = e.ends.filter(|_| e.alive) else {
                continue;
            };
            for (end, &node) in pair.iter().enumerate() {
                if node == n {
                    ends.push(((k, end), graph.leaving_direction(k, end)));
                }
            }
        }
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for i in 0..ends.len() {
            for j in i + 1..ends.len() {
                // Continuing from one branch into the other turns by the angle between the
                // first's arriving direction (−leaving) and the second's leaving one.
                let turn = angle_between(ends[i].1 * -1.0, ends[j].1);
                if turn <= max_turn {
                    pairs.push((turn, i, j));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut used = vec![false; ends.len()];
        for (_, i, j) in pairs {
            if used[i] || used[j] {
                continue;
            }
            used[i] = true;
            used[j] = true;
            let ((ki, ei), (kj, ej)) = (ends[i].0, ends[j].0);
            link[ki][ei] = Some((kj, ej));
            link[kj][ej] = Some((ki, ei));
        }
    }
    link
}
