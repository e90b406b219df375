// One prism of the fur's shell, shared by the shell pass and the volume pass. Mirrors
// `render::fur::shell_gpu::FurFace` (a test compares the layouts): prism f's base corners P_k and top corners
// T_k (w unused), the faces across its edges (edge e opposite corner e; 0xffffffff: none), its level d_f and
// the global index of its first sub-element.
struct FurFace {
    base: array<vec4<f32>, 3>,
    top: array<vec4<f32>, 3>,
    neighbours: array<u32, 3>,
    level: u32,
    offset: u32,
    pad: array<u32, 3>,
}
