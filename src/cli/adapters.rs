//! `hairlab adapters`: the GPU adapters wgpu finds on this machine, and the one hairlab would use.

use crate::gpu::{self, AdapterPreference, GpuError, REQUIRED_FEATURES};
use anyhow::Result;

pub(super) fn adapters() -> Result<()> {
    let adapters = gpu::enumerate_adapters();
    if adapters.is_empty() {
        return Err(GpuError::NoAdapter.into());
    }
    let chosen = gpu::select_adapter(
        &adapters,
        AdapterPreference::from_env_or(AdapterPreference::Hardware),
    )
    .map(|a| a.get_info());
    for a in &adapters {
        let info = a.get_info();
        let mark = if chosen.as_ref().is_ok_and(|c| *c == info) {
            "*"
        } else {
            " "
        };
        let missing = REQUIRED_FEATURES - a.features();
        let note = if missing.is_empty() {
            String::new()
        } else {
            format!(" — unusable, lacks {missing:?}")
        };
        println!(
            "{mark} {}, driver {} {}{note}",
            gpu::describe(&info),
            info.driver,
            info.driver_info
        );
    }
    match chosen {
        Ok(_) => println!(
            "(* marks the adapter hairlab uses; `--adapter NAME` or HAIRLAB_ADAPTER chooses another)"
        ),
        Err(e) => println!("hairlab can use none of them: {e}"),
    }
    Ok(())
}
