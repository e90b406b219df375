//! The reference's per-texel fragment lists of the current light view, read back from the A-buffer on demand and
//! cached: read again only when the scene's generation, the light, the map resolution or the hair alpha change, and not while
//! a drag is under way. [`read_reference_lists`] is the one place the app reads them from the renderer.

use crate::render::Renderer;
use crate::render::passes::abuffer::RefFragment;
use crate::scene::Light;
use crate::scene::pick;
use crate::settings::Settings;
use crate::visibility::Fragment;

/// What the reference fragment lists were read for.
#[derive(Clone, Debug, PartialEq)]
pub struct ListsKey {
    /// The renderer's scene generation (`Renderer::scene_generation`): it changes whenever the geometry does.
    scene: Option<u64>,
    /// The light, without intensity and colour (they do not move fragments).
    light: Light,
    map_resolution: u32,
    /// The hair alpha's bits, the alpha mode and the strand width's bits (they set the fragments' alphas).
    hair_alpha: u32,
    alpha: crate::render::AlphaMode,
    strand_width: u32,
}

impl ListsKey {
    /// The key of `settings` on the scene of generation `scene_generation`.
    pub fn new(settings: &Settings, scene_generation: Option<u64>) -> ListsKey {
        let mut light = settings.light;
        light.intensity = 0.0;
        light.color = [0.0; 3];
        ListsKey {
            scene: scene_generation,
            light,
            map_resolution: settings.render.light_map_side(),
            hair_alpha: settings.render.hair_alpha.to_bits(),
            alpha: settings.render.alpha,
            strand_width: settings.render.strand_width.to_bits(),
        }
    }
}

/// The reference's per-texel fragment lists of the current light view.
pub struct ReferenceLists {
    key: ListsKey,
    pub resolution: u32,
    /// Row-major texels (row 0 at the top of the map), each sorted by depth.
    pub lists: Vec<Vec<RefFragment>>,
    /// Increases with every read, so views of the lists know when to rebuild.
    pub generation: u64,
    densest: Option<[u32; 2]>,
}

impl ReferenceLists {
    /// `lists` holds `resolution²` texels (the A-buffer's heads), the resolution is taken from its length.
    fn new(key: ListsKey, lists: Vec<Vec<RefFragment>>, generation: u64) -> ReferenceLists {
        let resolution = lists.len().isqrt() as u32;
        let densest = lists
            .iter()
            .enumerate()
            .max_by_key(|(i, l)| (l.len(), std::cmp::Reverse(*i)))
            .filter(|(_, l)| !l.is_empty())
            .map(|(i, _)| [i as u32 % resolution, i as u32 / resolution]);
        ReferenceLists {
            key,
            resolution,
            lists,
            generation,
            densest,
        }
    }

    /// The list of texel `[x, y]` (`None` outside the map).
    fn list(&self, [x, y]: [u32; 2]) -> Option<&[RefFragment]> {
        let inside = x < self.resolution && y < self.resolution;
        inside
            .then(|| self.lists.get((y * self.resolution + x) as usize))
            .flatten()
            .map(Vec::as_slice)
    }

    /// The fragments of texel `[x, y]` (`None` outside the map).
    pub fn fragments(&self, texel: [u32; 2]) -> Option<Vec<Fragment>> {
        let list = self.list(texel)?;
        Some(list.iter().map(|f| f.fragment()).collect())
    }

    /// The texel holding the most fragments (the first in row-major order on ties), if any holds one.
    pub fn densest(&self) -> Option<[u32; 2]> {
        self.densest
    }

    /// The texel near `texel` holding a fragment of the picked `segment` at light depth `depth`
    /// ([`pick::resolve_pick`]).
    pub fn resolve_pick(&self, texel: [u32; 2], segment: u32, depth: f32) -> [u32; 2] {
        pick::resolve_pick(self.resolution, texel, segment, depth, |t| {
            self.list(t)
                .unwrap_or_default()
                .iter()
                .map(|f| (f.segment, f.depth))
        })
    }
}

/// The cached lists and what the last read was for.
#[derive(Default)]
pub(super) struct ListsCache {
    pub lists: Option<ReferenceLists>,
    /// The key of the last read attempt (a failed read is not retried until something changes).
    tried: Option<ListsKey>,
    /// The lists are older than the settings (a drag is under way).
    pub stale: bool,
    generation: u64,
}

impl ListsCache {
    /// Reads the lists again with `read` when `key` differs from theirs (and `allow`, i.e. no drag is under way);
    /// a failed read is not retried until the key changes. `Some` when a read was made: its outcome.
    pub fn refresh(
        &mut self,
        key: ListsKey,
        allow: bool,
        read: impl FnOnce() -> Result<Vec<Vec<RefFragment>>, String>,
    ) -> Option<Result<(), String>> {
        if self.lists.as_ref().is_some_and(|l| l.key == key) {
            self.stale = false;
            return None;
        }
        self.stale = self.lists.is_some();
        if !allow || self.tried.as_ref() == Some(&key) {
            return None;
        }
        self.tried = Some(key.clone());
        match read() {
            Ok(lists) => {
                self.generation += 1;
                self.lists = Some(ReferenceLists::new(key, lists, self.generation));
                self.stale = false;
                Some(Ok(()))
            }
            Err(e) => {
                self.lists = None;
                Some(Err(e))
            }
        }
    }

    /// The lists when they were read for `key`.
    pub fn current(&self, key: &ListsKey) -> Option<&ReferenceLists> {
        self.lists.as_ref().filter(|l| l.key == *key)
    }
}

/// The exact per-texel fragment lists of `settings`' light view ([`Renderer::reference_lists`]).
pub fn read_reference_lists(
    renderer: &mut Renderer,
    settings: &Settings,
) -> Result<Vec<Vec<RefFragment>>, String> {
    renderer
        .reference_lists(&settings.camera, &settings.light, &settings.render)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> ListsKey {
        ListsKey::new(&Settings::default(), None)
    }

    fn frag(depth: f32, segment: u32) -> RefFragment {
        RefFragment {
            depth,
            alpha: 0.5,
            segment,
        }
    }

    #[test]
    fn lists_give_texels_densest_and_picks() {
        // A 2² map, row-major: (0, 0) one fragment, (1, 0) none, (0, 1) two, (1, 1) two.
        let l = ReferenceLists::new(
            key(),
            vec![
                vec![frag(0.1, 4)],
                vec![],
                vec![frag(0.2, 4), frag(0.7, 9)],
                vec![frag(0.3, 9), frag(0.4, 9)],
            ],
            1,
        );
        assert_eq!(l.resolution, 2);
        assert_eq!(
            l.fragments([0, 1]),
            Some(vec![
                Fragment {
                    segment: 4,
                    ..Fragment::new(0.2, 0.5)
                },
                Fragment {
                    segment: 9,
                    ..Fragment::new(0.7, 0.5)
                }
            ])
        );
        assert_eq!(l.fragments([1, 0]), Some(vec![]));
        assert_eq!(l.fragments([2, 0]), None);
        // Two texels hold two fragments: the first in row-major order.
        assert_eq!(l.densest(), Some([0, 1]));
        // Segment 9 at depth 0.65 from (1, 0): (0, 1) and (1, 1) are both one texel away, 0.7 is closest.
        assert_eq!(l.resolve_pick([1, 0], 9, 0.65), [0, 1]);
        assert_eq!(l.resolve_pick([1, 0], 9, 0.35), [1, 1]);
        let empty = ReferenceLists::new(key(), vec![vec![]; 4], 1);
        assert_eq!(empty.densest(), None);
    }

    #[test]
    fn cache_reads_once_per_key_and_not_during_a_drag() {
        let mut cache = ListsCache::default();
        let read = |n: usize| move || Ok::<_, String>(vec![vec![frag(0.5, 0)]; n]);
        // A drag is under way: no read.
        assert_eq!(cache.refresh(key(), false, read(4)), None);
        assert!(cache.lists.is_none());
        assert_eq!(cache.refresh(key(), true, read(4)), Some(Ok(())));
        assert_eq!(
            cache.current(&key()).map(|l| (l.resolution, l.generation)),
            Some((2, 1))
        );
        // Same key: nothing read.
        assert_eq!(cache.refresh(key(), true, || Err("must not read".into())), None);
        // A new key during a drag: the old lists stay, stale.
        let mut moved = Settings::default();
        moved.light.azimuth_deg += 10.0;
        let moved = ListsKey::new(&moved, None);
        assert_eq!(cache.refresh(moved.clone(), false, read(9)), None);
        assert!(cache.stale && cache.current(&moved).is_none() && cache.lists.is_some());
        // A failed read drops the lists and is not retried for the same key.
        assert_eq!(
            cache.refresh(moved.clone(), true, || Err("boom".into())),
            Some(Err("boom".into()))
        );
        assert!(cache.lists.is_none());
        assert_eq!(cache.refresh(moved.clone(), true, read(9)), None);
        // Intensity and colour do not move fragments: the same key.
        let mut brighter = Settings::default();
        brighter.light.intensity *= 2.0;
        assert_eq!(ListsKey::new(&brighter, None), key());
        // The alpha mode and the strand width set the fragments' alphas: new keys.
        let mut coverage = Settings::default();
        coverage.render.alpha = crate::render::AlphaMode::Coverage;
        assert_ne!(ListsKey::new(&coverage, None), key());
        let mut wider = Settings::default();
        wider.render.strand_width *= 2.0;
        assert_ne!(ListsKey::new(&wider, None), key());
    }
}
