#include <atmoglobe/volume/ZipArchive.h>

#include <atmoglobe/volume/AtomicFile.h>

#include <zip.h>

#include <sys/stat.h>
#include <unistd.h>

namespace atmoglobe::volume {

Status writeZipArchiveAtomic(const std::string& path, const std::vector<ZipEntry>& entries) {
  if (entries.empty()) return makeError(path + ": a zip archive needs at least one entry");
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) return makeError(path + ": is a directory");
  Result<std::string> temp = temporaryPathBeside(path);
  if (!temp) return temp.forwardError();

  int openError = 0;
  zip_t* archive = zip_open(temp->c_str(), ZIP_CREATE | ZIP_EXCL, &openError);
  if (archive == nullptr) {
    zip_error_t error;
    zip_error_init_with_code(&error, openError);
    const std::string message = path + ": cannot create zip archive: " + zip_error_strerror(&error);
    zip_error_fini(&error);
    return makeError(message);
  }
  // Nothing is written before zip_close; on failure discard the archive and any temporary.
  auto fail = [&](const std::string& what) -> Status {
    const std::string message = path + ": " + what + ": " + zip_strerror(archive);
    zip_discard(archive);
    ::unlink(temp->c_str());
    return makeError(message);
  };
  for (const ZipEntry& e : entries) {
    // The buffer is not copied: `entries` outlives zip_close below.
    zip_source_t* source = zip_source_buffer(archive, e.bytes.data(), e.bytes.size(), 0);
    if (source == nullptr) return fail("cannot add " + e.name);
    const zip_int64_t index = zip_file_add(archive, e.name.c_str(), source, ZIP_FL_ENC_UTF_8);
    if (index < 0) {
      zip_source_free(source);  // not taken over by the archive when zip_file_add fails
      return fail("cannot add " + e.name);
    }
    const auto i = static_cast<zip_uint64_t>(index);
    if (zip_set_file_compression(archive, i, e.deflate ? ZIP_CM_DEFLATE : ZIP_CM_STORE, 0) != 0) {
      return fail("cannot set the compression of " + e.name);
    }
    if (zip_file_set_external_attributes(archive, i, 0, ZIP_OPSYS_UNIX, 0100644u << 16) != 0) {
      return fail("cannot set the attributes of " + e.name);  // regular file rw-r--r--
    }
    // Entry times: now, or $SOURCE_DATE_EPOCH when set (reproducible archives: the same scene gives
    // the same bytes; tests/tools/KillRandomly.cpp compares re-exports byte for byte).
    if (zip_file_set_mtime(archive, i, globe::outputTime(), 0) != 0) return fail("cannot set the time of " + e.name);
  }
  if (zip_close(archive) != 0) return fail("cannot write zip archive");
  return commitTemporary(*temp, path);
}

}  // namespace atmoglobe::volume
