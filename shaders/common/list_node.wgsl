// One light-space fragment in a texel's list of the reference A-buffer (render::passes::abuffer, NODE_BYTES):
// written by abuffer.wgsl, read by the reference lookup and by the compressors that build their maps from the
// lists (AVSM, compressed deep shadow maps).
struct ListNode {
    depth: f32,
    alpha: f32,
    segment: u32,
    // Index + 1 of the next node of the texel's list; 0 ends the list.
    next: u32,
}

// Pages the nodes span (1..=8, render::passes::list_pages::ListPipeline): an access tests the pages up to this count
// only, where the eight-way switch it replaces cost a CPU adapter all eight for every access (the list sort 4x
// its time at one page).
override list_pages: u32 = 8u;

// Page p's index of node i in pages of `size` nodes, and p.
fn list_page(i: u32, size: u32) -> vec2<u32> {
    let p = select(i / size, 0u, list_pages == 1u);
    return vec2<u32>(i - p * size, p);
}
