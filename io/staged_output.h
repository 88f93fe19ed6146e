// Output folders written all-or-nothing: files go to a staging folder, then take the output
// folder's place in one atomic step.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace hexmesh {

// Creates OUTDIR on construction (empty while the run works; a link to a folder stands for
// that folder) and locks it: a second process that constructs one for the same folder
// meanwhile is refused (std::runtime_error naming the folder). path(name) gives where to write
// an output: in a staging folder beside OUTDIR (OUTDIR/../.NAME.staging-HOST-PID). commit()
// carries the entries of OUTDIR that this run does not write (a user's notes, another
// format's export) into the staging folder (hard links, else copies), then swaps it with
// OUTDIR in one rename (Linux renameat2 RENAME_EXCHANGE) and removes the old contents: at
// every instant OUTDIR holds the complete previous result or the complete new one. On a file
// system without that exchange, the entries move one by one.
// Without commit() (an error on the way), the destructor removes the staging folder, and
// OUTDIR too if this object created it: no partial output is ever left under a final name.
// Staging folders of earlier runs on this host whose process is gone (killed before cleaning
// up) are removed on construction. Throws std::runtime_error if OUTDIR cannot be created.
// With Scope::named_entries (a file exported into any folder, a case's constant/polyMesh),
// only the entries written are replaced, each by one rename from a staging folder inside
// OUTDIR (OUTDIR/.staging-HOST-PID); the rest of the folder is not touched, nor locked.
class StagedOutput {
  public:
    enum class Scope { whole_folder, named_entries };
    explicit StagedOutput(std::string outdir, Scope scope = Scope::whole_folder);
    ~StagedOutput();
    StagedOutput(const StagedOutput&) = delete;
    StagedOutput& operator=(const StagedOutput&) = delete;

    std::string path(const std::string& name);
    // The staging folder itself, for other processes of the same job to write into (what they
    // write there is committed with the rest).
    const std::string& staging_folder() const { return staging_; }
    void write_text(const std::string& name, const std::string& text);
    // Moves the staged outputs into place; returns their final paths.
    std::vector<std::string> commit();

    // Tests only: called with "carried" (the staging folder complete) and "exchanged" (the
    // new result in place, the old one not yet removed) during commit(), e.g. to kill the
    // process there.
    static std::function<void(const char* step)> commit_step_hook;

  private:
    std::string outdir_, staging_;
    std::vector<std::string> names_;
    Scope scope_;
    int lock_fd_ = -1;
    bool created_outdir_ = false, committed_ = false;
};

}  // namespace hexmesh
