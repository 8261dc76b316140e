#pragma once
// Atomic file writes for volume/ writers: the one shared helper lives in globe/AtomicFile.h (the
// lowest library, so that globe's PNG and pyramid writers use it too); these are the same
// functions under the names volume/ has always used.
#include <atmoglobe/globe/AtomicFile.h>

namespace atmoglobe::volume {

using globe::AtomicFileSet;
using globe::AtomicFileWriter;
using globe::commitTemporary;
using globe::removeStaleTemporaries;
using globe::temporaryPathBeside;
using globe::writeFileAtomic;

}  // namespace atmoglobe::volume
