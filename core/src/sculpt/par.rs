//! Deterministic data parallelism for the per-frame passes, and an id sort.
//!
//! Every parallel pass here is a read-only map over fixed-size chunks of an
//! ordered input whose results are concatenated in input order, so its
//! output is the same, bit for bit, on any number of threads; small inputs
//! run on the calling thread (a thread hand-off costs more than they do).

use rayon::prelude::*;

/// Items per parallel chunk (fixed, so the split never depends on the
/// thread count).
pub(crate) const CHUNK: usize = 1024;
/// Inputs shorter than this run on the calling thread.
pub(crate) const PAR_MIN: usize = 4096;

/// `f` applied to each chunk of `items` (its items in order, plus the
/// index of its first item), outputs concatenated in input order.
pub(crate) fn flat_map_chunks<I, T, F>(items: &[I], f: F) -> Vec<T>
where
    I: Sync,
    T: Send,
    F: Fn(usize, &[I], &mut Vec<T>) + Sync + Send,
{
    let mut out = Vec::new();
    if items.len() < PAR_MIN {
        f(0, items, &mut out);
        return out;
    }
    let parts: Vec<Vec<T>> = items
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(k, c)| {
            let mut v = Vec::new();
            f(k * CHUNK, c, &mut v);
            v
        })
        .collect();
    out.reserve(parts.iter().map(Vec::len).sum());
    for p in parts {
        out.extend(p);
    }
    out
}

/// `f` applied to each chunk of `items` (plus the index of its first
/// item), one result per chunk in input order (for passes with several
/// outputs; the chunks are the same on any number of threads).
pub(crate) fn map_chunks<I, R, F>(items: &[I], f: F) -> Vec<R>
where
    I: Sync,
    R: Send,
    F: Fn(usize, &[I]) -> R + Sync + Send,
{
    if items.len() < PAR_MIN {
        return vec![f(0, items)];
    }
    items
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(k, c)| f(k * CHUNK, c))
        .collect()
}

/// `f` of every item, in order.
pub(crate) fn map<I, T, F>(items: &[I], f: F) -> Vec<T>
where
    I: Sync,
    T: Send,
    F: Fn(&I) -> T + Sync + Send,
{
    if items.len() < PAR_MIN {
        return items.iter().map(f).collect();
    }
    let mut out = Vec::with_capacity(items.len());
    out.par_extend(items.par_chunks(CHUNK).flat_map_iter(|c| c.iter().map(&f)));
    out
}

/// Sorts `v` by the `u32` key `key` (stable; an LSD radix sort in 11-bit
/// digits, skipping digits that are the same for every item), using
/// `scratch` as the second buffer. O(n) for the vertex and face ids the
/// frame passes sort, where a comparison sort was a visible share of a
/// frame.
pub(crate) fn sort_by_u32<T: Copy>(v: &mut Vec<T>, scratch: &mut Vec<T>, key: impl Fn(&T) -> u32) {
    if v.len() < 256 {
        v.sort_by_key(&key);
        return;
    }
    let (mut lo, mut hi) = (u32::MAX, 0u32);
    for x in v.iter() {
        let k = key(x);
        lo = lo.min(k);
        hi = hi.max(k);
    }
    const BITS: u32 = 11;
    const BUCKETS: usize = 1 << BITS;
    let mut shift = 0;
    while shift < 32 && ((lo ^ hi) >> shift) != 0 {
        let digit = |x: &T| ((key(x) >> shift) as usize) & (BUCKETS - 1);
        let mut count = [0usize; BUCKETS + 1];
        for x in v.iter() {
            count[digit(x) + 1] += 1;
        }
        for i in 0..BUCKETS {
            count[i + 1] += count[i];
        }
        scratch.clear();
        scratch.resize(v.len(), v[0]);
        for x in v.iter() {
            let d = digit(x);
            scratch[count[d]] = *x;
            count[d] += 1;
        }
        std::mem::swap(v, scratch);
        shift += BITS;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radix_sort_matches_a_stable_sort() {
        let mut seed = 12345u64;
        for n in [0usize, 1, 5, 255, 256, 1000, 70_000] {
            for range in [1u32, 7, 4096, 1 << 22, u32::MAX] {
                let mut v: Vec<(u32, usize)> = (0..n)
                    .map(|i| {
                        seed = seed
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        (((seed >> 32) as u32) % range.max(1), i)
                    })
                    .collect();
                let mut want = v.clone();
                want.sort_by_key(|x| x.0);
                sort_by_u32(&mut v, &mut Vec::new(), |x| x.0);
                assert_eq!(v, want, "n = {n}, range = {range}");
            }
        }
    }

    #[test]
    fn chunked_maps_keep_input_order() {
        let items: Vec<u32> = (0..20_000).collect();
        let doubled = map(&items, |&x| 2 * x);
        assert_eq!(doubled, items.iter().map(|&x| 2 * x).collect::<Vec<_>>());
        let odd = flat_map_chunks(&items, |start, c, out| {
            for (i, &x) in c.iter().enumerate() {
                assert_eq!(x as usize, start + i);
                if x % 2 == 1 {
                    out.push(x);
                }
            }
        });
        assert_eq!(odd, (0..20_000).filter(|x| x % 2 == 1).collect::<Vec<_>>());
    }
}
