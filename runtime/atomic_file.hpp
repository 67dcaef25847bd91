// Whole-or-nothing file replacement (spec §10: "an output file is either written
// whole or not touched"), and the removal of half-written temporaries when the
// process is ended by a signal.
//
// Every output Snell writes goes through write_file_atomically: the bytes go to
// a fresh temporary beside the final file, every write, the fsync and the close
// are checked, and only then is it renamed over the target (and the folder
// synced). A failure at any step removes the temporary and leaves the old file
// as it was. The limits: a hard link to the old file keeps the old contents (the
// name now points at a new inode, as with every rename-based writer); the owner
// is kept only when Snell runs with the right to chown.
#pragma once

#include <cstddef>
#include <string>

namespace snell::rt {

// Replaces `path` with `size` bytes at `data`. A symlink is written through: the
// file it points at (followed to the end of the chain) is replaced and the link
// is kept. An existing target keeps its permission bits; a new file gets 0666
// minus the umask, as open(2) would. Returns an error message naming `path`, or
// empty on success.
std::string write_file_atomically(const std::string& path, const void* data, std::size_t size);

// The file a write to `path` lands in: `path` with every symlink of its last
// component followed (relative links resolve against the link's folder). A
// dangling link gives the path it names; a loop gives `path` itself.
std::string write_target(const std::string& path);

// Installs handlers for SIGINT, SIGTERM, SIGHUP and SIGQUIT that remove the
// temporaries being written at that moment, then end the process by the same
// signal (its default action, so the exit status says which). Call once, early,
// from main. Without it a signal during a write leaves a hidden temporary. Also
// ignores SIGXFSZ, so a file-size limit is an I/O error of the write (EFBIG).
void remove_temporaries_on_signals();

}  // namespace snell::rt
