//! A directed graph of named nodes and its circles (strongly connected
//! components of more than one node, or a node with an arrow to itself).

use std::collections::{BTreeMap, BTreeSet, VecDeque};

/// Named nodes and the arrows between them, in a stable order.
#[derive(Default, Debug)]
pub struct Graph {
    arrows: BTreeMap<String, BTreeSet<String>>,
}

impl Graph {
    /// Adds a node without arrows.
    pub fn node(&mut self, name: &str) {
        self.arrows.entry(name.to_string()).or_default();
    }

    /// Adds the arrow `from -> to` (and both nodes).
    pub fn edge(&mut self, from: &str, to: &str) {
        self.node(to);
        self.arrows
            .entry(from.to_string())
            .or_default()
            .insert(to.to_string());
    }

    /// Whether the arrow `from -> to` is there.
    #[allow(dead_code)]
    pub fn has_edge(&self, from: &str, to: &str) -> bool {
        self.arrows.get(from).is_some_and(|t| t.contains(to))
    }

    fn next(&self, name: &str) -> impl Iterator<Item = &String> {
        self.arrows.get(name).into_iter().flatten()
    }
}

/// One loop per circle of `graph`: its nodes from the circle's first node
/// (in name order) around and back to it, the shortest such loop.
pub fn circles(graph: &Graph) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for component in components(graph) {
        let first = component.iter().next().expect("a component has nodes");
        let self_loop = graph.next(first).any(|n| n == first);
        if component.len() == 1 && !self_loop {
            continue;
        }
        out.push(shortest_loop(graph, first, &component));
    }
    out
}

/// The shortest path from `start` back to itself inside `within`.
fn shortest_loop(graph: &Graph, start: &str, within: &BTreeSet<String>) -> Vec<String> {
    let mut before: BTreeMap<String, String> = BTreeMap::new();
    let mut queue = VecDeque::from([start.to_string()]);
    while let Some(at) = queue.pop_front() {
        for next in graph.next(&at) {
            if !within.contains(next) {
                continue;
            }
            if next == start {
                let mut path = vec![start.to_string()];
                let mut node = at.clone();
                while node != start {
                    path.push(node.clone());
                    node = before[&node].clone();
                }
                path.push(start.to_string());
                path.reverse();
                return path;
            }
            if !before.contains_key(next) {
                before.insert(next.clone(), at.clone());
                queue.push_back(next.clone());
            }
        }
    }
    vec![start.to_string()]
}

/// The strongly connected components (Tarjan), each as a set of names.
fn components(graph: &Graph) -> Vec<BTreeSet<String>> {
    struct State<'a> {
        graph: &'a Graph,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        out: Vec<BTreeSet<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on_stack.insert(v);
        let graph = s.graph;
        for w in graph.next(v) {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[v].min(s.low[w]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.low[v].min(s.index[w]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = BTreeSet::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.insert(w.to_string());
                if w == v {
                    break;
                }
            }
            s.out.push(component);
        }
    }
    let mut state = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for name in graph.arrows.keys() {
        if !state.index.contains_key(name.as_str()) {
            visit(&mut state, name);
        }
    }
    state.out.sort();
    state.out
}
