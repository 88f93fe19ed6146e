// Output folders written all-or-nothing: files go to a staging folder, then move into place.
#pragma once

#include <string>
#include <vector>

namespace hexmesh {

// Creates OUTDIR (and a hidden staging folder inside it) on construction. path(name) gives
// where to write an output; commit() moves every staged entry to OUTDIR/name, replacing an
// older output of the same name. Without commit() (an error on the way), the destructor
// removes the staging folder, and OUTDIR too if this object created it: no partial output
// is ever left under a final name. The staging folder is OUTDIR/.staging-HOST-PID; those of
// earlier runs on this host whose process is gone (killed before cleaning up) are removed on
// construction. Throws std::runtime_error if OUTDIR cannot be created.
class StagedOutput {
public:
    explicit StagedOutput(std::string outdir);
    ~StagedOutput();
    StagedOutput(const StagedOutput&) = delete;
    StagedOutput& operator=(const StagedOutput&) = delete;

    std::string path(const std::string& name);
    void write_text(const std::string& name, const std::string& text);
    // Moves the staged outputs into place; returns their final paths.
    std::vector<std::string> commit();

private:
    std::string outdir_, staging_;
    std::vector<std::string> names_;
    bool created_outdir_ = false, committed_ = false;
};

}  // namespace hexmesh
