// The resident image server: an image helper (image_helper.hpp) that stays after
// its run, so that later runs of the same binary skip the image module's load —
// the ~0.25 s of dynamic linking that was the whole fixed cost of a small render
// (Debian's OIIO: 260 libraries, 168 k relocations; it cannot be made cheaper
// with the distribution's libraries). Images still go out through OIIO, encoded
// in the server, written by the run itself (whole or not at all).
//
// One server per user, binary and image environment: its socket is
// DIR/image-KEY.sock, where DIR is $SNELL_IMAGE_SERVER_DIR, else
// $XDG_RUNTIME_DIR/snell, else /tmp/snell-UID (made 0700; a directory that is not
// the user's own and private turns the server off), and KEY hashes the binary
// and its image module (their paths, inodes, sizes and times) and the variables that change what an
// encoder does (OCIO*, OPENIMAGEIO*, OIIO*, OPENEXR*, LD_*, SNELL_* but the server's own). A
// rebuilt binary or another OCIO gets a server of its own.
//
// The first run's helper becomes the server when its run ends (it has loaded the
// module, and loading it again would be the cost this saves; a fork of it is not
// an option: the libraries start threads as they load). The server lives in a
// session of its own, off every terminal, and ends once it has had no connection
// for $SNELL_IMAGE_SERVER_IDLE seconds (default 300), or once a newer server took
// its socket name. It serves only its own user (SO_PEERCRED). Limits: a server
// keeps the libraries it loaded, so an upgrade of OIIO reaches runs only once it
// has ended; an OCIO config given by a relative path is not sent to it (its working
// directory is /), such a run loads its own helper.
//
// SNELL_IMAGE_SERVER=0 turns it off (no connection, no server started);
// SNELL_IMAGE_HELPER=0 (in-process encoding) turns off both.
#pragma once

#include <optional>
#include <string>

#include "runtime/image_format.hpp"
#include "runtime/image_wire.hpp"

namespace snell::rt {

// The server's socket path for this binary and environment; empty when the server
// is off or its directory cannot be trusted.
std::string image_server_socket();

// Connects to the resident server and asks for its status with `check_display`
// (the display transform the run's outputs need): the connected socket, with the
// status message read into `status`; -1 when no server answers within a second
// or the server cannot serve this run.
int connect_image_server(const std::optional<DisplayView>& check_display, image_wire::Wire& status);

// The image helper child, once its run said goodbye (image_helper.hpp): becomes
// the resident server, unless the server is off or one answers already; never
// returns.
[[noreturn]] void become_image_server();

}  // namespace snell::rt
