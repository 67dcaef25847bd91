// The folder of decoded textures (§17): image files that are not linear are
// decoded once into linear, MIP-mapped .tx files (texture_io.cpp) and kept there
// for the next render. The folder is shared by every render of one user, so it
// must be the user's own, and bounded, since a user who renders many images
// fills it without limit otherwise.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>

namespace snell::rt {

// $SNELL_TEXTURE_CACHE, else $TMPDIR/snell-textures-UID (TMPDIR unset: /tmp),
// made with mode 0700 when missing. A folder another user made first (or any
// folder others can write to, or a symbolic link) is refused: its files would be
// read as this user's textures. Empty, with `error`, when refused or unmakeable.
std::filesystem::path texture_cache_dir(std::string& error);

// The cache's bound in bytes: $SNELL_TEXTURE_CACHE_MB megabytes, else 2048.
std::uint64_t texture_cache_max_bytes();

// Marks a cached file as used now (its modification time): pruning removes the
// least recently used first.
void texture_cache_touch(const std::filesystem::path& file);

// Bounds the folder: while its .tx files total more than max_bytes, removes the
// least recently used, except `keep` and files used within `grace` (a render in
// another process may still read them: OpenImageIO reopens files it closed to
// stay under its open-file limit). Also removes partial files (".*.tx") that a
// killed process left, once older than a day. Errors are ignored: a cache that
// cannot be pruned still works.
void texture_cache_prune(const std::filesystem::path& dir, std::uint64_t max_bytes,
                         std::chrono::seconds grace, const std::filesystem::path& keep);

}  // namespace snell::rt
