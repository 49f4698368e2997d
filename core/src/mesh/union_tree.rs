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
//! operand after it. Up to three operands the tree is the left fold, so
//! the bits of a union of three or fewer are what they were.
//!
//! The same shape, whatever the threads: each node is one Manifold
//! boolean of its two children, computed in parallel with `rayon::join`,
//! and Manifold's own parallel sites give the sequential bits, so the
//! union is the same bits on 1 or 2 threads (`tests/union_cache.rs`).

use std::sync::Arc;

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

/// What a union tree is evaluated with: the operands (`leaf`), the step
/// (`join`), and, for a caller that keeps nodes between evaluations, a
/// lookup (`found`) and a store (`keep`). `None` is an empty operand (and
/// a node all of whose operands are empty): a join with it is the other
/// side, as Manifold's batch union skips empty operands.
pub trait UnionTree: Sync {
    /// The united value (an imported Manifold mesh).
    type Value: Send + Sync;
    /// Why an operand or a step failed.
    type Error: Send;

    /// Operand `i`.
    fn leaf(&self, i: usize) -> Result<Option<Arc<Self::Value>>, Self::Error>;

    /// The union of two non-empty nodes.
    fn join(&self, a: &Self::Value, b: &Self::Value) -> Result<Self::Value, Self::Error>;

    /// The node `lo..hi` when it is kept from an earlier evaluation.
    fn found(&self, _lo: usize, _hi: usize) -> Option<Option<Arc<Self::Value>>> {
        None
    }

    /// Called with every node computed (not with those found).
    fn keep(&self, _lo: usize, _hi: usize, _value: &Option<Arc<Self::Value>>) {}
}

/// Evaluates the union tree over `n` operands (see the module doc), both
/// children of a node in parallel. Errors are reported in operand order:
/// of two failing children, the left one's (its operands come first).
pub fn unite_tree<T: UnionTree>(tree: &T, n: usize) -> Result<Option<Arc<T::Value>>, T::Error> {
    fn node<T: UnionTree>(
        tree: &T,
        lo: usize,
        hi: usize,
    ) -> Result<Option<Arc<T::Value>>, T::Error> {
        if let Some(v) = tree.found(lo, hi) {
            return Ok(v);
        }
        let value = if hi - lo == 1 {
            tree.leaf(lo)?
        } else {
            let mid = union_split(lo, hi);
            let (a, b) = rayon::join(|| node(tree, lo, mid), || node(tree, mid, hi));
            match (a?, b?) {
                (Some(a), Some(b)) => Some(Arc::new(tree.join(&a, &b)?)),
                (a, None) => a,
                (None, b) => b,
            }
        };
        tree.keep(lo, hi, &value);
        Ok(value)
    }
    if n == 0 {
        return Ok(None);
    }
    node(tree, 0, n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// The tree written out as a string of its joins.
    fn shape(n: usize) -> String {
        struct Show;
        impl UnionTree for Show {
            type Value = String;
            type Error = ();
            fn leaf(&self, i: usize) -> Result<Option<Arc<String>>, ()> {
                Ok(Some(Arc::new(i.to_string())))
            }
            fn join(&self, a: &String, b: &String) -> Result<String, ()> {
                Ok(format!("({a} {b})"))
            }
        }
        unite_tree(&Show, n)
            .expect("no errors")
            .map_or(String::new(), |s| (*s).clone())
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
            fn leaf(&self, i: usize) -> Result<Option<Arc<String>>, usize> {
                self.0.lock().expect("lock").push(i);
                match i {
                    1 | 4 => Ok(None),
                    5 | 6 => Err(i),
                    _ => Ok(Some(Arc::new(i.to_string()))),
                }
            }
            fn join(&self, a: &String, b: &String) -> Result<String, usize> {
                Ok(format!("({a} {b})"))
            }
        }
        let t = Sparse(Mutex::new(Vec::new()));
        let got = unite_tree(&t, 4).expect("no error among 0..4");
        assert_eq!(got.as_deref().map(String::as_str), Some("(0 (2 3))"));
        assert_eq!(unite_tree(&t, 8).err(), Some(5));
    }
}
