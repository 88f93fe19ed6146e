#include "io/vtk_support.h"

#include <fmt/format.h>
#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "io/input_error.h"

namespace hexmesh::vtk_support {
namespace {

// Keeps VTK's first message instead of printing it.
class CapturedMessages : public vtkOutputWindow {
  public:
    static CapturedMessages* New();
    vtkTypeMacro(CapturedMessages, vtkOutputWindow) void DisplayText(const char* text) override {
        keep(text);
    }
    void DisplayErrorText(const char* text) override { keep(text); }
    void DisplayWarningText(const char* text) override { keep(text); }
    void DisplayGenericWarningText(const char* text) override { keep(text); }
    void DisplayDebugText(const char*) override {}

    std::string take() {
        std::string m;
        std::swap(m, first_);
        while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
        const auto nl = m.rfind('\n');
        if (nl != std::string::npos) m = m.substr(nl + 1);
        const auto object = m.find("): ");
        if (object != std::string::npos && m.find(" (0x") < object) m = m.substr(object + 3);
        return m;
    }

  private:
    void keep(const char* text) {
        if (first_.empty() && text) first_ = text;
    }
    std::string first_;
};
vtkStandardNewMacro(CapturedMessages)

    CapturedMessages& messages() {
    static CapturedMessages* window = [] {
        auto* w = CapturedMessages::New();
        vtkOutputWindow::SetInstance(w);
        vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
        return w;
    }();
    return *window;
}

}  // namespace

std::string take_message() {
    return messages().take();
}

std::string extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return ext;
}

void check_written(int status, const std::string& path) {
    const std::string why = take_message();
    if (status != 1 || !why.empty())
        throw std::runtime_error(fmt::format("{}: VTK cannot write it: {}", path, why));
}

void configure_xml_writer(vtkXMLWriterBase& writer) {
    writer.SetDataModeToAppended();
    writer.EncodeAppendedDataOff();
    writer.SetCompressorTypeToNone();
    writer.SetHeaderTypeToUInt64();
}

void require_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw InputError(fmt::format("{}: no such mesh file", path));
}

void check_cell_points(vtkIdList* ids, int count, Id points, const std::string& path,
                       vtkIdType cell) {
    if (ids->GetNumberOfIds() < count)
        throw InputError(fmt::format("{}: cell {} has {} point ids where its type takes {}", path,
                                     cell, ids->GetNumberOfIds(), count));
    for (vtkIdType v = 0; v < ids->GetNumberOfIds(); ++v)
        if (ids->GetId(v) < 0 || ids->GetId(v) >= points)
            throw InputError(
                fmt::format("{}: cell {} refers to point {}, but the file has points 0 to {}", path,
                            cell, ids->GetId(v), points - 1));
}

}  // namespace hexmesh::vtk_support
