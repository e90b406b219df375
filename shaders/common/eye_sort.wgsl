// The eye lists' sort, written for 64 keys: one bottom-up merge pass of runs of `width`, and the whole sort of
// a pixel's gathered keys. Included between a resolve's `template begin` and `template end`, so it is
// instantiated for every sort size with the resolve (src/render/transparency/sorted.rs, `resolve_source`); the
// including file defines `Key` and `before`.
// One bottom-up merge pass of runs of `width` from `src` into `dst`.
fn merge_pass_64(src: ptr<function, array<Key, 64u>>, dst: ptr<function, array<Key, 64u>>, n: u32, width: u32) {
    var start = 0u;
    loop {
        if start >= n {
            break;
        }
        let mid = min(start + width, n);
        let end = min(start + 2u * width, n);
        var i = start;
        var j = mid;
        var k = start;
        loop {
            if k >= end {
                break;
            }
            if i < mid && (j >= end || !before((*src)[j], (*src)[i])) {
                (*dst)[k] = (*src)[i];
                i += 1u;
            } else {
                (*dst)[k] = (*src)[j];
                j += 1u;
            }
            k += 1u;
        }
        start = end;
    }
}

// Sorts the first `n` keys of `a` (using `b` as scratch); true when the result is in `a`.
fn sort_64(a: ptr<function, array<Key, 64u>>, b: ptr<function, array<Key, 64u>>, n: u32) -> bool {
    var width = 1u;
    var in_a = true;
    loop {
        if width >= n {
            break;
        }
        if in_a {
            merge_pass_64(a, b, n, width);
        } else {
            merge_pass_64(b, a, n, width);
        }
        in_a = !in_a;
        width *= 2u;
    }
    return in_a;
}
