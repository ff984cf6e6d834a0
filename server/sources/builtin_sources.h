// Registers the source types that need no hardware: `images` and `replay`.
#pragma once

namespace omniview {

// Call once at start-up, before configs are read (idempotent).
void register_builtin_sources();

}  // namespace omniview
