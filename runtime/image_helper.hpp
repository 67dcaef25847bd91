// The image helper: a child process that loads the image module (OIIO and OCIO,
// ~0.25 s of dynamic linking on Debian's build: 260 libraries, 168 k relocations)
// while `snell render` parses, builds and renders, and then encodes the images the
// render writes. The load cannot be cut while images go out through Debian's
// OIIO, and on a thread beside the render it is slower than before it (its loader
// lock stalls Embree's and TBB's thread start-up); in a process of its own it
// overlaps the work and takes only the cores the render leaves it.
//
// Only the encoding moves: the file itself is still written by this process,
// whole or not at all (write_file_atomically), so the signal handler and the
// fault tests see the one writer they always did. The child never writes a file
// or the terminal; it ends when this process closes its socket or dies
// (PR_SET_PDEATHSIG), and an encoder that crashes there is an error message here.
//
// The load is the whole fixed cost of a small render, so a helper that loaded
// leaves a resident image server behind (image_server.hpp): a later run on the
// same binary connects to it and forks no helper at all.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/image_format.hpp"

namespace snell::rt {

struct Image;
struct OutputInfo;

// Forks the helper. Call while the process has one thread (before any render or
// texture system): the child runs dlopen, which a fork taken beside other threads
// could find locked. With `check_display` the child also makes that display
// transform once loaded (what the PNG/JPEG/TIFF outputs will need). Does nothing
// (write_image then loads the module in process) when fork fails, when a helper
// already runs, or when SNELL_IMAGE_HELPER=0 is set in the environment.
void start_image_helper(const std::optional<DisplayView>& check_display);

// Who encodes this run's images, for --stats: "the resident image server", "a
// helper process" or "this process".
std::string image_writer_kind();

// Whether a helper was started and not stopped. write_image encodes through it;
// one that died makes every write report how (image_helper_status).
bool image_helper_running();

// What the helper found: why the module could not be loaded, or why the display
// transform could not be made (both empty: ready). A helper that ended on its own
// is a load error naming how it ended.
struct ImageHelperStatus {
  std::string load_error;
  std::string display_error;
};
// The helper's status; with `wait` false, nullopt while it is still loading.
// Thread-safe (the render's progress callback asks from its workers).
std::optional<ImageHelperStatus> image_helper_status(bool wait);

// Ends the helper and reaps it (kills one still loading); write_image then loads
// the module in process. For a scene whose §17 images need the module here anyway.
// With `leave_resident` (a run's end), a helper that loaded is left to become the
// resident server (image_server.hpp) instead.
void stop_image_helper(bool leave_resident = false);

// Encodes `image` as write_image would in process, through the helper: the error
// message (the encoder's own, or how the helper failed), or empty with `bytes`.
std::string image_helper_encode(const std::string& path, const Image& image, const OutputInfo& info,
                                const DisplayView& display, std::vector<unsigned char>& bytes);

// The encoder in this process, through the image module (image_out.cpp): what
// write_image runs without a helper, and what the helper runs for it.
std::string encode_image_here(const std::string& path, const Image& image, const OutputInfo& info,
                              const DisplayView& display, std::vector<unsigned char>& bytes);

}  // namespace snell::rt
