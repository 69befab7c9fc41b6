//! Ground-graph search on the reference scene: the hand-written Dijkstra
//! (`graph::search`) against petgraph's `dijkstra` and `astar` on the same
//! edges: `cargo bench -p skyground-core --bench search`.
//!
//! - `search/all_nodes_custom`, `search/all_nodes_petgraph_dijkstra`: distances
//!   from the start to every node (what each row of the route's matrix needs);
//! - `search/point_to_point_custom`, `search/point_to_point_petgraph_astar`:
//!   one path between the two nodes farthest apart along x.

#[path = "../tests/planning_scene/mod.rs"]
mod planning_scene;

use std::hint::black_box;

use criterion::Criterion;
use petgraph::algo::{astar, dijkstra};
use petgraph::graph::{NodeIndex, UnGraph};
use planning_scene::{start, world};
use skyground_core::graph::{GraphParams, GroundGraph};

fn benches(c: &mut Criterion) {
    let w = world();
    let g = GroundGraph::build(&w.xyz, &w.labels, start(w), &GraphParams::default()).unwrap();
    let pos = g.positions().to_vec();
    let mut pg = UnGraph::<(), f32>::with_capacity(pos.len(), 0);
    for _ in &pos {
        pg.add_node(());
    }
    for (a, b, w) in g.edges() {
        pg.add_edge(NodeIndex::new(a), NodeIndex::new(b), w);
    }
    let s = g.start_node();
    let by_x = |far: bool| {
        (0..pos.len())
            .max_by(|&i, &j| {
                let o = pos[i][0].total_cmp(&pos[j][0]);
                if far { o } else { o.reverse() }
            })
            .unwrap_or(0)
    };
    let (a, b) = (by_x(false), by_x(true));
    let custom = g.shortest_path(a, b).map(|(d, _)| d);
    let h = |n: NodeIndex| {
        let (p, q) = (pos[n.index()], pos[b]);
        // Straight-line distance in plan: never more than any path's length.
        (p[0] - q[0]).hypot(p[1] - q[1])
    };
    let pet_astar = |from: NodeIndex| astar(&pg, from, |n| n.index() == b, |e| *e.weight(), h);
    let pet = pet_astar(NodeIndex::new(a)).map(|(d, _)| d);
    println!(
        "search: {} nodes, {} edges; {a} → {b}: custom {custom:?} m, petgraph A* {pet:?} m",
        pg.node_count(),
        pg.edge_count()
    );
    let mut group = c.benchmark_group("search");
    group.sample_size(20);
    group.bench_function("all_nodes_custom", |bch| {
        bch.iter(|| g.shortest_paths(black_box(&[s])).dist.len())
    });
    group.bench_function("all_nodes_petgraph_dijkstra", |bch| {
        bch.iter(|| dijkstra(&pg, black_box(NodeIndex::new(s)), None, |e| *e.weight()).len())
    });
    group.bench_function("point_to_point_custom", |bch| {
        bch.iter(|| g.shortest_path(black_box(a), b))
    });
    group.bench_function("point_to_point_petgraph_astar", |bch| {
        bch.iter(|| pet_astar(black_box(NodeIndex::new(a))))
    });
    group.finish();
}

criterion::criterion_group!(group, benches);
criterion::criterion_main!(group);
