//! Quadratic triangle meshes of plane regions: constrained Delaunay triangulation with quality
//! refinement (Ruppert-type refinement of the `spade` crate), then 6-node triangles with the
//! mid-edge nodes of circular boundaries placed on the circle.

use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use crate::error::{Error, Result};
use crate::geometry::Vec2;

/// What a boundary loop is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoopKind {
    /// The outer outline (the disc profile).
    Outline,
    /// Crank bearing bore `k` (tied to its crank centre by a rigid spider).
    CrankBore(usize),
    /// A traction-free hole (output-pin hole, centre hole), index `k` in the order given.
    Hole(usize),
}

/// A closed boundary loop, sampled as a polygon (m). Circles carry their centre and radius so
/// that mid-edge nodes lie on the true circle.
#[derive(Debug, Clone)]
pub struct BoundaryLoop {
    /// Vertices of the polygon, in order (the closing edge is implied).
    pub points: Vec<Vec2>,
    /// Kind of boundary.
    pub kind: LoopKind,
    /// `(centre, radius)` for a circle, m.
    pub circle: Option<(Vec2, f64)>,
}

impl BoundaryLoop {
    /// A circle of radius `r` (m) about `c`, with `n` vertices.
    pub fn circle(c: Vec2, r: f64, n: usize, kind: LoopKind) -> Self {
        let n = n.max(8);
        let points = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                c + crate::geometry::portable::unit(a) * r
            })
            .collect();
        BoundaryLoop {
            points,
            kind,
            circle: Some((c, r)),
        }
    }
}

/// One edge of the mesh boundary: 3 nodes (the two corners and the mid-edge node).
#[derive(Debug, Clone, Copy)]
pub struct BoundaryEdge {
    /// `[start, end, mid]` node indices.
    pub nodes: [usize; 3],
    /// The loop it lies on.
    pub kind: LoopKind,
}

/// A mesh of 6-node (quadratic) triangles.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Node positions, m.
    pub nodes: Vec<Vec2>,
    /// Elements: corners `0, 1, 2` counter-clockwise, then the mid-edge nodes of the edges
    /// `0-1`, `1-2`, `2-0`.
    pub triangles: Vec<[usize; 6]>,
    /// Boundary edges with the loop each lies on.
    pub boundary: Vec<BoundaryEdge>,
    /// Number of corner nodes (they come first in `nodes`).
    pub corner_nodes: usize,
}

/// Mesh refinement settings.
#[derive(Debug, Clone, Copy)]
pub struct MeshSpec {
    /// Largest triangle area, m^2.
    pub max_area: f64,
    /// Smallest angle the refinement aims for, degrees (spade refines up to about 30).
    pub min_angle_deg: f64,
    /// Most vertices the refinement may add before giving up (memory guard).
    pub max_added_vertices: usize,
}

/// Meshes the region inside `loops[0]`'s outline and outside the other loops with quadratic
/// triangles.
///
/// # Errors
/// [`Error::Invalid`] if the loops cross each other; [`Error::Numerical`] if the refinement
/// does not complete within `spec.max_added_vertices`.
pub(crate) fn triangulate(loops: &[BoundaryLoop], spec: &MeshSpec) -> Result<Mesh> {
    let mut vertices = Vec::new();
    let mut edges = Vec::new();
    for l in loops {
        let base = vertices.len();
        let n = l.points.len();
        for p in &l.points {
            vertices.push(Point2::new(p.x, p.y));
        }
        for k in 0..n {
            edges.push([base + k, base + (k + 1) % n]);
        }
    }
    let mut conflict = false;
    let mut cdt =
        ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(vertices, edges, |_| {
            conflict = true
        })
        .map_err(|e| Error::numerical("disc mesh", format!("triangulation failed: {e:?}")))?;
    if conflict {
        return Err(Error::invalid(
            "fem holes",
            "overlapping boundaries",
            "the crank bores, holes and the tooth outline must not cut each other",
        ));
    }
    let result = cdt.refine(
        RefinementParameters::<f64>::new()
            .exclude_outer_faces(true)
            .with_angle_limit(AngleLimit::from_deg(spec.min_angle_deg))
            .with_max_allowed_area(spec.max_area)
            .with_max_additional_vertices(spec.max_added_vertices),
    );
    if !result.refinement_complete {
        return Err(Error::numerical(
            "disc mesh",
            format!(
                "refinement stopped after {} added vertices (fem.max_memory_gb guard)",
                spec.max_added_vertices
            ),
        ));
    }
    let mut excluded = vec![false; cdt.num_all_faces()];
    for f in &result.excluded_faces {
        excluded[f.index()] = true;
    }
    let corner_nodes = cdt.num_vertices();
    let mut nodes: Vec<Vec2> = cdt
        .vertices()
        .map(|v| Vec2::new(v.position().x, v.position().y))
        .collect();
    let mut used = vec![false; corner_nodes];
    let mut tris: Vec<[usize; 3]> = Vec::new();
    for f in cdt.inner_faces() {
        if excluded[f.fix().index()] {
            continue;
        }
        let v = f.vertices().map(|v| v.fix().index());
        let (a, b, c) = (nodes[v[0]], nodes[v[1]], nodes[v[2]]);
        let area = 0.5 * ((b - a).perp(&(c - a)));
        let t = if area > 0.0 {
            [v[0], v[1], v[2]]
        } else {
            [v[0], v[2], v[1]]
        };
        for &i in &t {
            used[i] = true;
        }
        tris.push(t);
    }
    if tris.is_empty() {
        return Err(Error::numerical(
            "disc mesh",
            "no triangles inside the outline",
        ));
    }
    // Renumber the corners that are used (refinement may leave vertices in excluded regions).
    let mut map = vec![usize::MAX; corner_nodes];
    let mut corners = Vec::new();
    for (i, u) in used.iter().enumerate() {
        if *u {
            map[i] = corners.len();
            corners.push(nodes[i]);
        }
    }
    nodes = corners;
    let corner_nodes = nodes.len();
    // Mid-edge nodes, shared through a map of sorted corner pairs.
    let mut edge_mid: std::collections::HashMap<(usize, usize), (usize, usize)> =
        std::collections::HashMap::with_capacity(tris.len() * 2);
    let mut triangles = Vec::with_capacity(tris.len());
    for t in &tris {
        let c = [map[t[0]], map[t[1]], map[t[2]]];
        let mut mids = [0usize; 3];
        for e in 0..3 {
            let (a, b) = (c[e], c[(e + 1) % 3]);
            let key = (a.min(b), a.max(b));
            let entry = edge_mid.entry(key).or_insert_with(|| {
                nodes.push((nodes[a] + nodes[b]) * 0.5);
                (nodes.len() - 1, 0)
            });
            entry.1 += 1;
            mids[e] = entry.0;
        }
        triangles.push([c[0], c[1], c[2], mids[0], mids[1], mids[2]]);
    }
    // Boundary edges: used by one triangle, in that triangle's (counter-clockwise) direction.
    let mut boundary = Vec::new();
    for t in &triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let (mid, count) = edge_mid[&(a.min(b), a.max(b))];
            if count == 1 {
                let m = (nodes[a] + nodes[b]) * 0.5;
                let kind = classify(loops, &m);
                if let Some(l) = loops.iter().find(|l| l.kind == kind) {
                    if let Some((c, r)) = l.circle {
                        let d = m - c;
                        nodes[mid] = c + d * (r / d.norm());
                    }
                }
                boundary.push(BoundaryEdge {
                    nodes: [a, b, mid],
                    kind,
                });
            }
        }
    }
    Ok(Mesh {
        nodes,
        triangles,
        boundary,
        corner_nodes,
    })
}

/// The loop a boundary point lies on: the circle it is on (relative tolerance 2e-2 of the
/// radius, far above the chord sag of the sampled circles), otherwise the outline.
fn classify(loops: &[BoundaryLoop], m: &Vec2) -> LoopKind {
    for l in loops {
        if let Some((c, r)) = l.circle {
            if ((m - c).norm() - r).abs() < 2e-2 * r {
                return l.kind;
            }
        }
    }
    loops
        .iter()
        .find(|l| l.circle.is_none())
        .map(|l| l.kind)
        .unwrap_or(LoopKind::Outline)
}
