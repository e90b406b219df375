//! glTF 2.0 (`.gltf` / `.glb`) loading: triangles become opaque [`Mesh`]es, lines become hair [`Strands`].
//!
//! The default scene (else the first scene, else every root node) is walked with node world transforms
//! applied. Triangle lists, strips and fans become one mesh per primitive, coloured by the material's base
//! colour factor; normals come from the file (through the normal matrix) or are computed. `LINES` primitives
//! are chained into strands while each segment starts where the previous one ended (same index or same
//! position); each `LINE_STRIP` is one strand. `COLOR_0` gives strand colours (and per-point alpha when it
//! has four components). `POINTS` and `LINE_LOOP` primitives are skipped with a warning. Only buffers are
//! loaded: images are not decoded, so a missing or broken texture does not stop a scene from loading.
//!
//! Before the `gltf` crate sees the file, `gltf_check` reads it bounded and checks the glb header, the buffer
//! URIs and every accessor the loader reads, so that the crate neither over-allocates nor panics on our input.
//! A panic it still raises is caught without its text ([`load_gltf`]) and becomes [`GltfError::Malformed`].

use std::cell::Cell;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

use glam::{Mat3, Mat4, Vec3};
use gltf::mesh::Mode;
use gltf::mesh::util::ReadColors;
use thiserror::Error;

use super::gltf_check;
use super::{Mesh, Scene, Strands};

thread_local! {
    /// Set while [`load_gltf`] runs the parser on this thread: its panics are caught and reported as errors.
    static QUIET: Cell<bool> = const { Cell::new(false) };
}

/// Installs (once) a panic hook that stays silent for the panics [`load_gltf`] catches and hands every other panic
/// to the hook it replaced.
fn install_quiet_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(Cell::get) {
                previous(info);
            }
        }));
    });
}

/// Everything that can go wrong loading a glTF file; every message names the file.
#[derive(Debug, Error)]
pub enum GltfError {
    #[error("{path}: {cause}")]
    Gltf { path: PathBuf, cause: gltf::Error },
    #[error("{path}: malformed glTF: {message}")]
    Malformed { path: PathBuf, message: String },
    #[error("{path}: contains no triangles or lines")]
    NoGeometry { path: PathBuf },
    #[error("{path}: {primitive}: has no readable POSITION attribute")]
    NoPositions { path: PathBuf, primitive: String },
    #[error("{path}: {primitive}: indices could not be read from their buffer")]
    BadIndices { path: PathBuf, primitive: String },
    #[error("{path}: {primitive}: index {index} is out of range for {vertices} vertices")]
    IndexOutOfRange {
        path: PathBuf,
        primitive: String,
        index: u32,
        vertices: usize,
    },
    #[error("{path}: {primitive}: vertex {vertex} has a non-finite position {position}")]
    NonFinitePosition {
        path: PathBuf,
        primitive: String,
        vertex: usize,
        position: Vec3,
    },
}

/// Loads the triangles and lines of a glTF file into a [`Scene`].
pub fn load_gltf(path: &Path) -> Result<Scene, GltfError> {
    install_quiet_hook();
    QUIET.with(|q| q.set(true));
    // Everything the closure touches is created inside it, so nothing is left half-updated by a panic.
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| load(path)));
    QUIET.with(|q| q.set(false));
    result.unwrap_or_else(|payload| {
        let detail = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(GltfError::Malformed {
            path: path.to_owned(),
            message: format!("the glTF reader gave up on it ({detail})"),
        })
    })
}

fn load(path: &Path) -> Result<Scene, GltfError> {
    let gltf_err = |cause| GltfError::Gltf {
        path: path.to_owned(),
        cause,
    };
    let malformed = |message| GltfError::Malformed {
        path: path.to_owned(),
        message,
    };
    let bytes = crate::io::read_regular_file(path).map_err(|e| malformed(format!("cannot read: {e}")))?;
    gltf_check::check_glb(&bytes).map_err(|e| malformed(e.to_string()))?;
    // The crate's own validation indexes without checking: our index checks come first.
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(&bytes).map_err(gltf_err)?;
    gltf_check::check_indices(&document).map_err(|e| malformed(e.to_string()))?;
    let document = gltf::Document::from_json(document.into_json()).map_err(gltf_err)?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    gltf_check::check_buffer_uris(&document, dir).map_err(|e| malformed(e.to_string()))?;
    let buffers = gltf::import_buffers(&document, Some(dir), blob).map_err(gltf_err)?;
    gltf_check::check_accessors(&document, &buffers).map_err(|e| malformed(e.to_string()))?;
    let mut loader = Loader {
        path,
        buffers: &buffers,
        meshes: Vec::new(),
        strands: Strands::default(),
    };

    let roots: Vec<gltf::Node> = match document.default_scene().or_else(|| document.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: HashSet<usize> = document
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()).collect::<Vec<_>>())
                .collect();
            document
                .nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    };
    // Iterative walk; a node seen twice (only possible in an invalid file with cycles or shared children) is
    // skipped so the walk always ends.
    let mut seen = HashSet::new();
    let mut stack: Vec<(gltf::Node, Mat4)> = roots.into_iter().rev().map(|n| (n, Mat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        if !seen.insert(node.index()) {
            log::warn!(
                "{}: node {} is reached twice; skipping it the second time",
                path.display(),
                node.index()
            );
            continue;
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            loader.mesh(&mesh, &world)?;
        }
        let children: Vec<gltf::Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
    }

    if loader.meshes.is_empty() && loader.strands.strand_count() == 0 {
        return Err(GltfError::NoGeometry {
            path: path.to_owned(),
        });
    }
    Ok(Scene::new(loader.strands, loader.meshes))
}

struct Loader<'a> {
    path: &'a Path,
    buffers: &'a [gltf::buffer::Data],
    meshes: Vec<Mesh>,
    strands: Strands,
}

/// Vertex data of one primitive, positions already in world space.
struct Vertices {
    positions: Vec<Vec3>,
    /// Vertex indices in primitive order (implicit `0..n` when the primitive has none).
    indices: Vec<u32>,
}

impl Loader<'_> {
    fn mesh(&mut self, mesh: &gltf::Mesh, world: &Mat4) -> Result<(), GltfError> {
        for prim in mesh.primitives() {
            let label = match mesh.name() {
                Some(name) => format!("mesh {} ('{name}') primitive {}", mesh.index(), prim.index()),
                None => format!("mesh {} primitive {}", mesh.index(), prim.index()),
            };
            match prim.mode() {
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => {
                    self.triangles(&prim, world, &label)?
                }
                Mode::Lines | Mode::LineStrip => self.lines(&prim, world, &label)?,
                mode @ (Mode::Points | Mode::LineLoop) => {
                    log::warn!("{}: {label}: skipping {mode:?} primitive", self.path.display())
                }
            }
        }
        Ok(())
    }

    fn vertices(&self, prim: &gltf::Primitive, world: &Mat4, label: &str) -> Result<Vertices, GltfError> {
        let reader = prim.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| GltfError::NoPositions {
                path: self.path.to_owned(),
                primitive: label.to_owned(),
            })?
            .map(|p| world.transform_point3(Vec3::from_array(p)))
            .collect();
        if let Some((vertex, &position)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(GltfError::NonFinitePosition {
                path: self.path.to_owned(),
                primitive: label.to_owned(),
                vertex,
                position,
            });
        }
        let indices: Vec<u32> = match prim.indices() {
            Some(_) => reader
                .read_indices()
                .ok_or_else(|| GltfError::BadIndices {
                    path: self.path.to_owned(),
                    primitive: label.to_owned(),
                })?
                .into_u32()
                .collect(),
            None => (0..positions.len() as u32).collect(),
        };
        if let Some(&index) = indices.iter().find(|&&i| i as usize >= positions.len()) {
            return Err(GltfError::IndexOutOfRange {
                path: self.path.to_owned(),
                primitive: label.to_owned(),
                index,
                vertices: positions.len(),
            });
        }
        Ok(Vertices { positions, indices })
    }

    fn triangles(&mut self, prim: &gltf::Primitive, world: &Mat4, label: &str) -> Result<(), GltfError> {
        let Vertices { positions, indices } = self.vertices(prim, world, label)?;
        let mut tris: Vec<[u32; 3]> = match prim.mode() {
            Mode::TriangleStrip => indices
                .windows(3)
                .enumerate()
                .filter_map(|(i, w)| match *w {
                    [a, b, c] if i % 2 == 0 => Some([a, b, c]),
                    [a, b, c] => Some([b, a, c]),
                    _ => None,
                })
                .collect(),
            Mode::TriangleFan => match indices.split_first() {
                Some((&first, rest)) => rest
                    .windows(2)
                    .filter_map(|w| {
                        if let [b, c] = *w {
                            Some([b, c, first])
                        } else {
                            None
                        }
                    })
                    .collect(),
                None => Vec::new(),
            },
            _ => indices.as_chunks::<3>().0.to_vec(),
        };
        if tris.is_empty() {
            return Ok(());
        }
        // A mirroring transform turns the winding inside out; swap two corners to keep front faces in front.
        let mirrored = world.determinant() < 0.0;
        if mirrored {
            tris.iter_mut().for_each(|t| t.swap(1, 2));
        }
        let base = prim.material().pbr_metallic_roughness().base_color_factor();
        let mut mesh = Mesh {
            normals: Vec::new(),
            indices: tris.into_iter().flatten().collect(),
            color: Vec3::new(base[0], base[1], base[2]),
            positions,
        };
        let normal_matrix = Mat3::from_mat4(*world).inverse().transpose();
        let reader = prim.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
        let file_normals: Option<Vec<Vec3>> = reader.read_normals().and_then(|n| {
            n.map(|n| (normal_matrix * Vec3::from_array(n)).try_normalize())
                .collect::<Option<Vec<Vec3>>>()
        });
        match file_normals {
            Some(n) if n.len() == mesh.positions.len() => mesh.normals = n,
            _ => mesh.compute_normals(),
        }
        self.meshes.push(mesh);
        Ok(())
    }

    fn lines(&mut self, prim: &gltf::Primitive, world: &Mat4, label: &str) -> Result<(), GltfError> {
        let Vertices { positions, indices } = self.vertices(prim, world, label)?;
        let reader = prim.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
        // Colours as rgba, and whether the file gave an alpha channel.
        let colors: Option<(Vec<[f32; 4]>, bool)> = reader.read_colors(0).map(|c| {
            let has_alpha = matches!(
                c,
                ReadColors::RgbaU8(_) | ReadColors::RgbaU16(_) | ReadColors::RgbaF32(_)
            );
            (c.into_rgba_f32().collect(), has_alpha)
        });
        let colors = match colors {
            Some((c, _)) if c.len() != positions.len() => {
                log::warn!(
                    "{}: {label}: COLOR_0 has {} entries for {} vertices; ignoring it",
                    self.path.display(),
                    c.len(),
                    positions.len()
                );
                None
            }
            c => c,
        };

        // Each strand as a list of vertex indices.
        let mut chains: Vec<Vec<u32>> = Vec::new();
        if prim.mode() == Mode::LineStrip {
            chains.push(indices);
        } else {
            let (pairs, rest) = indices.as_chunks::<2>();
            if !rest.is_empty() {
                log::warn!(
                    "{}: {label}: odd LINES index count; ignoring the last index",
                    self.path.display()
                );
            }
            let pos = |i: u32| positions.get(i as usize).copied();
            for &[a, b] in pairs {
                match chains.last_mut() {
                    Some(chain) if chain.last().is_some_and(|&l| l == a || pos(l) == pos(a)) => chain.push(b),
                    _ => chains.push(vec![a, b]),
                }
            }
        }

        for chain in chains {
            if chain.len() < 2 {
                log::warn!(
                    "{}: {label}: skipping a strand with fewer than 2 points",
                    self.path.display()
                );
                continue;
            }
            let points: Vec<Vec3> = chain
                .iter()
                .filter_map(|&i| positions.get(i as usize).copied())
                .collect();
            let rgba: Option<Vec<[f32; 4]>> = colors
                .as_ref()
                .map(|(c, _)| chain.iter().filter_map(|&i| c.get(i as usize).copied()).collect());
            let has_alpha = colors.as_ref().is_some_and(|(_, a)| *a);
            let strand = Strands {
                counts: vec![points.len() as u32],
                points,
                thickness: None,
                alpha: rgba
                    .as_ref()
                    .filter(|_| has_alpha)
                    .map(|c| c.iter().map(|c| c[3]).collect()),
                color: rgba.map(|c| c.iter().map(|c| Vec3::new(c[0], c[1], c[2])).collect()),
            };
            self.strands.append(&strand);
        }
        Ok(())
    }
}
