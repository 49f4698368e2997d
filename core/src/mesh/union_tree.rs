//! The fixed shape in which a union of `n` operands is united, and its
//! evaluation with both halves of every node in parallel (issue 37:
//! "unite independent pairs in parallel in a fixed tree, so the bits do
//! not depend on threads").
//!
//! Manifold's `batch_boolean` (and our union until issue 37) is a left
//! fold: `((a ∪ b) ∪ c) ∪ …`, one step after the other, each step
//! carrying everything united so far, so `n` parts cost about `n²/2`
//! part-sized booleans and leave a second core idle. A balanced tree costs
//! about `n log n` and unites its two halves at once. Its shape here is
//! the binary counter's:
//!
//! - a *block* of `2^k` operands starting at a multiple of `2^k` is the
//!   union of its two halves;
//! - the *prefix* `0..n` is, when `n` is not a power of two, the prefix
//!   `0..n - lowbit(n)` united with the block `n - lowbit(n)..n`
//!   (`lowbit(n)` the largest power of two dividing `n`); so `0..n` is the
//!   left fold of its maximal aligned blocks, largest first.
//!
//! So every node's shape depends only on its range, and a node of the
//! tree for `n` operands is the same node in the tree for `n + 1`
//! whenever its range is: the assembly cache ([`crate::assembly`]) keeps
//! nodes by their content. Adding an operand to an even number unites it
//! with the union of the others, found whole (`0..n` is the new root's
//! left child); to an odd number, it unites the nodes on the path from
//! the new leaf to the root, at most `log2(n + 1) + 1` of them and of
//! doubling sizes, so about twice the left fold's one step. An edit of
//! one operand re-unites that path, where the left fold re-unites every
//! operand after it. Up to three groups the tree is the left fold.
//!
//! Its leaves are *groups* of operands whose bounding boxes are pairwise
//! disjoint ([`disjoint_groups`], C++ Manifold's `BatchUnion`
//! partition): a group's union is the concatenation of its operands, with
//! no boolean at all, so the four legs of a chair are one leaf and the
//! chair's nine parts take one boolean, not eight. A group is made at
//! once, its operands' meshes side by side imported as one mesh, all
//! groups in parallel, errors in operand order. (Importing each operand
//! and then composing them, as C++ does, cost twice as much here:
//! manifold-rust's `Compose` rebuilds the halfedges and cleans up again,
//! where C++ copies them; the chair's groups took 43 and 88-96 ms that
//! way, 23 and 40-42 ms imported whole.)
//!
//! The same shape, whatever the threads: each node is one Manifold
//! boolean of its two children, computed in parallel with `rayon::join`,
//! and Manifold's own parallel sites give the sequential bits, so the
//! union is the same bits on 1 or 2 threads (`tests/suite/union_cache.rs`).

use std::collections::HashMap;
use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;

/// Where the node `lo..hi` of the union tree splits (`hi - lo >= 2`; see
/// the module doc): its left child is `lo..split`, its right `split..hi`.
pub fn union_split(lo: usize, hi: usize) -> usize {
    let len = hi - lo;
    debug_assert!(len >= 2, "a leaf does not split");
    if len.is_power_of_two() {
        lo + len / 2
    } else {
        // Only a prefix (lo = 0) has a length that is not a power of two.
        debug_assert_eq!(lo, 0, "an aligned block has a power-of-two length");
        hi - (1 << hi.trailing_zeros())
    }
}

/// Every node `(lo, hi)` of the union tree over `n` operands, leaves
/// (`hi = lo + 1`) included, each child before its parent, the root
/// `(0, n)` last (none for `n = 0`).
pub fn union_tree_nodes(n: usize) -> Vec<(usize, usize)> {
    fn walk(lo: usize, hi: usize, out: &mut Vec<(usize, usize)>) {
        if hi - lo >= 2 {
            let mid = union_split(lo, hi);
            walk(lo, mid, out);
            walk(mid, hi, out);
        }
        out.push((lo, hi));
    }
    let mut out = Vec::with_capacity(2 * n);
    if n > 0 {
        walk(0, n, &mut out);
    }
    out
}

/// C++ Manifold's partition of a batch union's operands: each operand,
/// in order, joins the first group none of whose members' boxes overlaps
/// its box, or starts a new group. Boxes that touch, or come within a
/// billionth of their coordinates' size of each other, overlap: a box
/// computed from a mesh before a boolean trimmed it may miss the trimmed
/// mesh by a rounding, and composing two operands that meet would be
/// wrong. Operands without a box (empty) are left out. A pure function of
/// the boxes, so of the operands.
pub fn disjoint_groups(boxes: &[Option<(DVec3, DVec3)>]) -> Vec<Vec<usize>> {
    let overlap = |a: (DVec3, DVec3), b: (DVec3, DVec3)| {
        let size = [a.0, a.1, b.0, b.1]
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        let pad = DVec3::splat(1e-9 * size);
        a.0.cmple(b.1 + pad).all() && b.0.cmple(a.1 + pad).all()
    };
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, b) in boxes.iter().enumerate() {
        let Some(b) = *b else { continue };
        let free =
            |g: &&mut Vec<usize>| g.iter().all(|&j| boxes[j].is_some_and(|c| !overlap(b, c)));
        match groups.iter_mut().find(free) {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
}

/// What a union tree is evaluated with: the union of a group of
/// disjoint operands (`group`) and of two nodes (`join`), and, for a
/// caller that keeps nodes between evaluations, a lookup (`found`) and a
/// store (`keep`) of a node, named by the groups under it (an operand
/// alone is the node `&[vec![i]]`). `None` is an empty operand (and a
/// node all of whose operands are empty): a join with it is the other
/// side, as Manifold's batch union skips empty operands.
pub trait UnionTree: Sync {
    /// The united value (an imported Manifold mesh).
    type Value: Send + Sync;
    /// Why an operand or a step failed.
    type Error: Send;

    /// The union of the operands `members` (in operand order; their
    /// boxes pairwise disjoint, or one operand alone): their meshes side
    /// by side, no boolean. On failure, the first member that fails (in
    /// operand order, as making them one by one would find) and why.
    fn group(&self, members: &[usize]) -> Made<Self>;

    /// The union of two non-empty nodes.
    fn join(&self, a: &Self::Value, b: &Self::Value) -> Result<Self::Value, Self::Error>;

    /// The node over `groups` when it is kept from an earlier evaluation.
    fn found(&self, _groups: &[Vec<usize>]) -> Option<Option<Arc<Self::Value>>> {
        None
    }

    /// Called with every node computed (not with those found).
    fn keep(&self, _groups: &[Vec<usize>], _value: &Option<Arc<Self::Value>>) {}
}

/// A node: `None` when every operand under it is empty.
pub type Node<T> = Option<Arc<<T as UnionTree>::Value>>;
/// A group made ([`UnionTree::group`]), or its first failing operand and
/// why.
pub type Made<T> = Result<Node<T>, (usize, <T as UnionTree>::Error)>;

/// What is left to compute of a node once what is kept is found.
enum Plan<V> {
    Found(Option<Arc<V>>),
    Group(usize),
    Join(usize, usize, Box<Plan<V>>, Box<Plan<V>>),
}

/// Evaluates the union tree over `groups` (see the module doc; from
/// [`disjoint_groups`], or one operand a group for a plain tree): the
/// nodes kept are looked up from the root down, the groups still needed
/// are made in parallel (the error of the first failing operand in operand
/// order reported), then the nodes are joined, both children of a node at
/// once (of two failing children, the left one's error is reported).
pub fn unite_tree<T: UnionTree>(tree: &T, groups: &[Vec<usize>]) -> Result<Node<T>, T::Error> {
    fn plan<T: UnionTree>(tree: &T, groups: &[Vec<usize>], lo: usize, hi: usize) -> Plan<T::Value> {
        if let Some(v) = tree.found(&groups[lo..hi]) {
            return Plan::Found(v);
        }
        if hi - lo == 1 {
            return Plan::Group(lo);
        }
        let mid = union_split(lo, hi);
        let (a, b) = (plan(tree, groups, lo, mid), plan(tree, groups, mid, hi));
        Plan::Join(lo, hi, Box::new(a), Box::new(b))
    }
    fn needed<V>(p: &Plan<V>, out: &mut Vec<usize>) {
        match p {
            Plan::Found(_) => {}
            Plan::Group(g) => out.push(*g),
            Plan::Join(_, _, a, b) => {
                needed(a, out);
                needed(b, out);
            }
        }
    }
    fn run<T: UnionTree>(
        tree: &T,
        groups: &[Vec<usize>],
        made: &HashMap<usize, Node<T>>,
        p: Plan<T::Value>,
    ) -> Result<Node<T>, T::Error> {
        let (range, value) = match p {
            Plan::Found(v) => return Ok(v),
            // Made (and kept) with the other groups, before any join.
            Plan::Group(g) => return Ok(made.get(&g).cloned().flatten()),
            Plan::Join(lo, hi, a, b) => {
                let (a, b) = rayon::join(
                    || run(tree, groups, made, *a),
                    || run(tree, groups, made, *b),
                );
                let value = match (a?, b?) {
                    (Some(a), Some(b)) => Some(Arc::new(tree.join(&a, &b)?)),
                    (a, None) => a,
                    (None, b) => b,
                };
                (lo..hi, value)
            }
        };
        tree.keep(&groups[range], &value);
        Ok(value)
    }
    if groups.is_empty() {
        return Ok(None);
    }
    let root = plan(tree, groups, 0, groups.len());
    let mut ids = Vec::new();
    needed(&root, &mut ids);
    ids.sort_unstable();
    let made: Vec<Made<T>> = ids
        .par_iter()
        .map(|&g| {
            let v = tree.group(&groups[g])?;
            tree.keep(&groups[g..g + 1], &v);
            Ok(v)
        })
        .collect();
    let mut by_group = HashMap::with_capacity(ids.len());
    // Groups interleave in operand order ({0, 3} and {1, 2}): the error
    // reported is the one of the first failing operand, whichever group.
    let mut first_error: Option<(usize, T::Error)> = None;
    for (g, v) in ids.into_iter().zip(made) {
        match v {
            Ok(v) => {
                by_group.insert(g, v);
            }
            Err((i, e)) => {
                if first_error.as_ref().is_none_or(|(j, _)| i < *j) {
                    first_error = Some((i, e));
                }
            }
        }
    }
    if let Some((_, e)) = first_error {
        return Err(e);
    }
    run(tree, groups, &by_group, root)
}

/// One operand a group: the plain tree over `n` operands.
pub fn singletons(n: usize) -> Vec<Vec<usize>> {
    (0..n).map(|i| vec![i]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// The tree over `groups` written out: `(a b)` a join, `{a b}` a
    /// group imported as one.
    fn grouped(groups: &[Vec<usize>]) -> String {
        struct Show;
        impl UnionTree for Show {
            type Value = String;
            type Error = ();
            fn group(&self, members: &[usize]) -> Result<Option<Arc<String>>, (usize, ())> {
                let parts: Vec<String> = members.iter().map(usize::to_string).collect();
                Ok(Some(Arc::new(match parts.len() {
                    1 => parts[0].clone(),
                    _ => format!("{{{}}}", parts.join(" ")),
                })))
            }
            fn join(&self, a: &String, b: &String) -> Result<String, ()> {
                Ok(format!("({a} {b})"))
            }
        }
        unite_tree(&Show, groups)
            .expect("no errors")
            .map_or(String::new(), |s| (*s).clone())
    }

    /// The plain tree over `n` operands, written out.
    fn shape(n: usize) -> String {
        grouped(&singletons(n))
    }

    #[test]
    fn disjoint_operands_are_composed_into_one_leaf() {
        let cube = |lo: f64, hi: f64| Some((DVec3::splat(lo), DVec3::splat(hi)));
        // A seat overlapping four legs that do not meet each other; the
        // last leg's box touches the third's corner (touching overlaps),
        // and an empty operand has no box.
        let boxes = [
            cube(0.0, 10.0),
            cube(0.0, 1.0),
            cube(2.0, 3.0),
            cube(5.0, 6.0),
            None,
            cube(6.0, 7.0),
        ];
        let groups = disjoint_groups(&boxes);
        assert_eq!(groups, vec![vec![0], vec![1, 2, 3], vec![5]]);
        assert_eq!(grouped(&groups), "((0 {1 2 3}) 5)");
    }

    #[test]
    fn the_tree_is_the_left_fold_up_to_three_then_balanced_blocks() {
        assert_eq!(shape(0), "");
        assert_eq!(shape(1), "0");
        assert_eq!(shape(2), "(0 1)");
        assert_eq!(shape(3), "((0 1) 2)");
        assert_eq!(shape(4), "((0 1) (2 3))");
        assert_eq!(shape(5), "(((0 1) (2 3)) 4)");
        assert_eq!(shape(6), "(((0 1) (2 3)) (4 5))");
        assert_eq!(shape(7), "((((0 1) (2 3)) (4 5)) 6)");
        assert_eq!(shape(9), "((((0 1) (2 3)) ((4 5) (6 7))) 8)");
    }

    #[test]
    fn nodes_list_the_tree_children_first_and_reuse_the_smaller_tree() {
        for n in 1..40 {
            let nodes = union_tree_nodes(n);
            assert_eq!(nodes.len(), 2 * n - 1, "n = {n}");
            assert_eq!(nodes.last(), Some(&(0, n)));
            for (k, &(lo, hi)) in nodes.iter().enumerate() {
                if hi - lo >= 2 {
                    let mid = union_split(lo, hi);
                    assert!(nodes[..k].contains(&(lo, mid)) && nodes[..k].contains(&(mid, hi)));
                }
            }
            // Adding an operand keeps every node of the smaller tree but
            // those on the path to its new root: what an added part re-unites.
            let next = union_tree_nodes(n + 1);
            let new = next.iter().filter(|x| !nodes.contains(x)).count();
            assert!(
                new <= 1 + (n + 1).ilog2() as usize,
                "n = {n}: {new} new nodes"
            );
        }
    }

    #[test]
    fn empty_operands_are_skipped_and_errors_come_in_operand_order() {
        struct Sparse(Mutex<Vec<usize>>);
        impl UnionTree for Sparse {
            type Value = String;
            type Error = usize;
            fn group(&self, members: &[usize]) -> Result<Option<Arc<String>>, (usize, usize)> {
                let mut made = Vec::new();
                for &i in members {
                    self.0.lock().expect("lock").push(i);
                    match i {
                        1 | 4 => {}
                        3 | 5 | 6 => return Err((i, i)),
                        _ => made.push(i.to_string()),
                    }
                }
                Ok((!made.is_empty()).then(|| Arc::new(made.join("+"))))
            }
            fn join(&self, a: &String, b: &String) -> Result<String, usize> {
                Ok(format!("({a} {b})"))
            }
        }
        let t = Sparse(Mutex::new(Vec::new()));
        let got = unite_tree(&t, &[vec![0], vec![1], vec![2, 7]]).expect("no error");
        assert_eq!(got.as_deref().map(String::as_str), Some("(0 2+7)"));
        assert_eq!(unite_tree(&t, &singletons(8)).err(), Some(3));
        // Groups made in parallel, interleaved in operand order: the first
        // failing operand's error, not the first failing group's.
        assert_eq!(unite_tree(&t, &[vec![0, 6], vec![5, 7]]).err(), Some(5));
        assert_eq!(unite_tree(&t, &[vec![0, 5], vec![2, 3]]).err(), Some(3));
        // Every group is made once per evaluation, before any join.
        let mut made = t.0.into_inner().expect("lock");
        made.sort_unstable();
        assert_eq!(
            made,
            [0, 0, 0, 0, 1, 1, 2, 2, 2, 3, 3, 4, 5, 5, 5, 6, 6, 7, 7]
        );
    }
}
