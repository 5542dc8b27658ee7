// Files the user keeps (goldens, manifests, reports, bench results) are replaced whole: written
// to a temporary sibling, flushed, then renamed over the target, so a reader, or the next run
// after a SIGKILL, sees the old file or the new one and never a part.
//
// Temporary siblings are named ".parity-tmp-<pid>-<random>-<file name>": the pid lets a later
// run remove what a killed writer left (removeStaleTemporaries), the file name keeps the
// extension that OpenImageIO chooses the format by.
#pragma once

#include <string>

namespace parity::harness {

// A fresh temporary name beside `target`, in the same folder (rename is atomic there only).
std::string temporarySibling(const std::string& target);

// Writes text to path atomically; the folder is created. False with "PATH: cannot write (why)".
bool writeFileAtomic(const std::string& path, const std::string& text, std::string* error);
// Copies a file atomically over `to` (same rule).
bool copyFileAtomic(const std::string& from, const std::string& to, std::string* error);

// Removes the temporary siblings under `folder` (and its subfolders when `recursive`) whose
// writing process no longer exists; those of live processes (a concurrent writer) are kept.
// Returns how many were removed. A missing folder is not an error.
int removeStaleTemporaries(const std::string& folder, bool recursive);

// A step of an atomic write (temporary created, half written, flushed, renamed). Tests stop the
// process at the Nth step with PARITY_KILL_AT_WRITE_STEP=N (SIGKILL, nothing is cleaned up), so
// that tests/reliability_kill_test.cpp can interrupt bless and report writes at every point.
void atomicWriteStep();

}  // namespace parity::harness
