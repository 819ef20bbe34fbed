// lsds.open, lsds.Collection, lsds.Frame, lsds.Camera and lsds.Bundle (docs/python.md).
#include "python/bindings.h"

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "python/json_to_python.h"
#include "python/open_collection.h"
#include "python/usage_error.h"

namespace lsds::python {

namespace py = pybind11;

namespace {

using Shared = std::shared_ptr<const OpenCollection>;

// `values` moved to the heap, and a capsule that frees them: the base of a NumPy array over them.
template <typename T>
std::pair<const T*, py::capsule> Own(std::vector<T>&& values) {
  auto* owner = new std::vector<T>(std::move(values));
  return {owner->data(),
          py::capsule(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); })};
}

// A NumPy array over `values`, which it owns (no copy).
template <typename T>
py::array ArrayOf(std::vector<T>&& values, const std::vector<int64_t>& shape) {
  auto [data, base] = Own(std::move(values));
  return py::array_t<T>(std::vector<py::ssize_t>(shape.begin(), shape.end()), data, base);
}

py::array Matrix(const Eigen::MatrixXd& m) {
  py::array_t<double> out({m.rows(), m.cols()});
  auto view = out.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) view(r, c) = m(r, c);
  return std::move(out);
}

struct PyCamera {
  CameraTruth truth;
  nlohmann::json json;

  Eigen::Matrix4d CamFromWorld() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = truth.cam_from_world_rotation;
    m.topRightCorner<3, 1>() = truth.cam_from_world_translation;
    return m;
  }
  // The inverse; the rotation is orthogonal (determinant -1 in a left-handed world).
  Eigen::Matrix4d WorldFromCam() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = truth.cam_from_world_rotation.transpose();
    m.topRightCorner<3, 1>() =
        -truth.cam_from_world_rotation.transpose() * truth.cam_from_world_translation;
    return m;
  }
  Eigen::Matrix3d K() const {
    const PinholeCamera& c = truth.intrinsics;
    Eigen::Matrix3d k;
    k << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1;
    return k;
  }
};

struct PyBundle {
  int width = 0, height = 0;
  py::array counts, offsets, samples;

  py::object Pixel(int x, int y) const {
    if (x < 0 || y < 0 || x >= width || y >= height) {
      throw py::index_error("pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                            ") is outside the " + std::to_string(width) + "x" +
                            std::to_string(height) + " image");
    }
    const auto* first =
        static_cast<const uint64_t*>(offsets.data()) + static_cast<size_t>(y) * width + x;
    return samples[py::slice(
        static_cast<py::ssize_t>(first[0]), static_cast<py::ssize_t>(first[1]), 1)];
  }
};

PyBundle ToBundle(BundleArrays&& b) {
  PyBundle out;
  out.width = b.width;
  out.height = b.height;
  py::list fields;
  for (const exr::ChannelSpec& f : b.fields)
    fields.append(py::make_tuple(f.name, f.type == exr::PixelType::kUint ? "<u4" : "<f4"));
  const py::dtype record = py::dtype::from_args(fields);
  const auto samples = static_cast<int64_t>(b.offsets.empty() ? 0 : b.offsets.back());
  auto [data, base] = Own(std::move(b.records));
  out.samples = py::array(record, std::vector<py::ssize_t>{samples}, data, base);
  out.counts = ArrayOf(std::move(b.counts), {b.height, b.width});
  const auto offsets = static_cast<int64_t>(b.offsets.size());
  out.offsets = ArrayOf(std::move(b.offsets), {offsets});
  return out;
}

class PyFrame {
 public:
  PyFrame(Shared collection, size_t position)
      : collection_(std::move(collection)), position_(position) {}

  const Frame& frame() const { return collection_->frame(position_); }
  const nlohmann::json& json() const { return collection_->frame_json(position_); }
  py::object Member(const char* key) const {
    const auto it = json().find(key);
    return it == json().end() ? py::none() : ToPython(*it);
  }

  py::array Layer(const std::string& name, bool channels_first) const {
    LayerArray layer;
    {
      py::gil_scoped_release release;
      layer = collection_->ReadLayer(position_, name, channels_first);
    }
    if (layer.integer) return ArrayOf(std::move(layer.uints), layer.shape);
    return ArrayOf(std::move(layer.floats), layer.shape);
  }

  PyBundle Bundle(const std::string& name) const {
    BundleArrays bundle;
    {
      py::gil_scoped_release release;
      bundle = collection_->ReadBundle(position_, name);
    }
    return ToBundle(std::move(bundle));
  }

  py::object Metadata() const {
    const nlohmann::json* record = collection_->metadata(frame().index);
    return record != nullptr ? ToPython(*record) : py::none();
  }

  PyCamera Camera() const {
    const auto it = json().find("camera");
    return {frame().camera, it == json().end() ? nlohmann::json() : *it};
  }

  std::string Repr() const {
    const Frame& f = frame();
    std::string repr = "<lsds.Frame " + std::to_string(f.index);
    if (f.rig_camera) repr += " (" + *f.rig_camera + ")";
    return repr + " t=" + FormatNumber(f.time) + " s, " + std::to_string(f.objects.size()) +
           " objects>";
  }

 private:
  Shared collection_;
  size_t position_;
};

class PyCollection {
 public:
  explicit PyCollection(Shared collection) : collection_(std::move(collection)) {}

  size_t Size() const { return collection_->size(); }
  PyFrame At(py::ssize_t position) const {
    const auto size = static_cast<py::ssize_t>(Size());
    if (position < 0) position += size;
    if (position < 0 || position >= size) {
      throw py::index_error("frame position " + std::to_string(position) + " is outside 0.." +
                            std::to_string(size - 1));
    }
    return {collection_, static_cast<size_t>(position)};
  }
  py::list Slice(const py::slice& slice) const {
    py::ssize_t start = 0, stop = 0, step = 0, length = 0;
    if (!slice.compute(static_cast<py::ssize_t>(Size()), &start, &stop, &step, &length))
      throw py::error_already_set();
    py::list frames;
    for (py::ssize_t i = 0; i < length; ++i)
      frames.append(PyFrame(collection_, static_cast<size_t>(start + i * step)));
    return frames;
  }
  PyFrame ByIndex(int64_t index) const {
    const std::optional<size_t> position = collection_->PositionOfIndex(index);
    if (!position) {
      throw py::key_error("the collection " + collection_->reader().root().string() +
                          " has no frame with index " + std::to_string(index));
    }
    return {collection_, *position};
  }
  py::object Header(const char* key) const {
    const nlohmann::json& header = collection_->header_json();
    const auto it = header.find(key);
    return it == header.end() ? py::none() : ToPython(*it);
  }
  const OpenCollection& data() const { return *collection_; }

 private:
  Shared collection_;
};

PyCollection Open(const std::filesystem::path& path,
                  int threads,
                  const std::optional<std::string>& metadata) {
  if (threads < 1) throw UsageError("threads must be at least 1, got " + std::to_string(threads));
  std::shared_ptr<const OpenCollection> collection;
  {
    py::gil_scoped_release release;
    collection = std::make_shared<const OpenCollection>(path, threads, metadata.value_or(""));
  }
  return PyCollection(std::move(collection));
}

void RegisterCamera(py::module_& m) {
  py::class_<PyCamera>(
      m, "Camera", "A frame's camera: intrinsics and pose as collection.json declares them.")
      .def_property_readonly(
          "K",
          [](const PyCamera& c) { return Matrix(c.K()); },
          "3x3 intrinsics [[fx, 0, cx], [0, fy, cy], [0, 0, 1]], float64; cx, cy in "
          "pixel-edge coordinates (pixel (i, j) covers [i, i+1) x [j, j+1))")
      .def_property_readonly(
          "cam_from_world",
          [](const PyCamera& c) { return Matrix(c.CamFromWorld()); },
          "4x4 float64: point_in_cam = cam_from_world @ [point_in_world, 1] "
          "(OpenCV camera frame: x right, y down, z forward)")
      .def_property_readonly(
          "world_from_cam",
          [](const PyCamera& c) { return Matrix(c.WorldFromCam()); },
          "4x4 float64, the inverse of cam_from_world")
      .def_property_readonly("width", [](const PyCamera& c) { return c.truth.intrinsics.width; })
      .def_property_readonly("height", [](const PyCamera& c) { return c.truth.intrinsics.height; })
      .def_property_readonly(
          "json",
          [](const PyCamera& c) { return ToPython(c.json); },
          "the frame's camera object of collection.json")
      .def("__repr__", [](const PyCamera& c) {
        return "<lsds.Camera " + std::to_string(c.truth.intrinsics.width) + "x" +
               std::to_string(c.truth.intrinsics.height) + ">";
      });
}

void RegisterBundle(py::module_& m) {
  py::class_<PyBundle>(
      m,
      "Bundle",
      "A frame's pixel bundle: every sub-pixel sample of every pixel, as ragged arrays.")
      .def_readonly("width", &PyBundle::width)
      .def_readonly("height", &PyBundle::height)
      .def_readonly("counts", &PyBundle::counts, "samples per pixel, uint32 (height, width)")
      .def_readonly("offsets",
                    &PyBundle::offsets,
                    "uint64 (height * width + 1,): pixel p = y * width + x has the samples "
                    "offsets[p]:offsets[p + 1]")
      .def_readonly("samples",
                    &PyBundle::samples,
                    "structured array, one record per sample: instanceid, classid (uint32), Z, "
                    "NX, NY, NZ, SX, SY (float32) for a bundle")
      .def("pixel", &PyBundle::Pixel, py::arg("x"), py::arg("y"), "the samples of pixel (x, y)")
      .def("__len__", [](const PyBundle& b) { return b.samples.size(); });
}

void RegisterFrame(py::module_& m) {
  py::class_<PyFrame>(m, "Frame", "One frame of a collection: its truth, camera and layers.")
      .def_property_readonly("index", [](const PyFrame& f) { return f.frame().index; })
      .def_property_readonly(
          "time", [](const PyFrame& f) { return f.frame().time; }, "seconds")
      .def_property_readonly("sequence", [](const PyFrame& f) { return f.frame().sequence; })
      .def_property_readonly("shot", [](const PyFrame& f) { return f.frame().shot; })
      .def_property_readonly("rig_camera", [](const PyFrame& f) { return f.frame().rig_camera; })
      .def_property_readonly("step", [](const PyFrame& f) { return f.frame().step; })
      .def_property_readonly(
          "files",
          [](const PyFrame& f) { return f.Member("files"); },
          "layer name -> path relative to the collection folder")
      .def_property_readonly(
          "objects",
          [](const PyFrame& f) { return f.Member("objects"); },
          "the objects' truth, as collection.json holds it (list of dicts)")
      .def_property_readonly("camera", &PyFrame::Camera)
      .def_property_readonly("metadata",
                             &PyFrame::Metadata,
                             "the frame's record of metadata.json (measured platform and camera), "
                             "or None")
      .def_property_readonly(
          "json",
          [](const PyFrame& f) { return ToPython(f.json()); },
          "the frame as collection.json holds it")
      .def("layer",
           &PyFrame::Layer,
           py::arg("name"),
           py::kw_only(),
           py::arg("channels_first") = false,
           "the flat layer `name` decoded: float32 (HALF and FLOAT channels) or uint32 (ids), "
           "shape (height, width) or (height, width, channels) in the layer table's channel order; "
           "with channels_first=True (channels, height, width), one-channel layers included")
      .def("bundle",
           &PyFrame::Bundle,
           py::arg("name") = "",
           "the deep layer `name` (default: the bundle) decoded into an lsds.Bundle")
      .def("__repr__", &PyFrame::Repr);
}

void RegisterCollectionClass(py::module_& m) {
  // Iteration is the sequence protocol's: __getitem__ from 0 until IndexError.
  py::class_<PyCollection>(m, "Collection", "An open lsds collection: a sequence of frames.")
      .def("__len__", &PyCollection::Size)
      .def("__getitem__", &PyCollection::At, py::arg("position"))
      .def("__getitem__", &PyCollection::Slice, py::arg("positions"))
      .def_property_readonly(
          "frames",
          [](const py::object& self) { return self; },
          "the collection itself, a sequence of frames (c.frames[0] is c[0])")
      .def("frame",
           &PyCollection::ByIndex,
           py::arg("index"),
           "the frame whose index (collection.json's `index`) is `index`; KeyError if none")
      .def_property_readonly(
          "path", [](const PyCollection& c) { return c.data().reader().root().string(); })
      .def_property_readonly("format_version",
                             [](const PyCollection& c) { return c.Header("format_version"); })
      .def_property_readonly("classes", [](const PyCollection& c) { return c.Header("classes"); })
      .def_property_readonly("layers", [](const PyCollection& c) { return c.Header("layers"); })
      .def_property_readonly("rig", [](const PyCollection& c) { return c.Header("rig"); })
      .def_property_readonly("provenance",
                             [](const PyCollection& c) { return c.Header("provenance"); })
      .def_property_readonly("conventions",
                             [](const PyCollection& c) { return c.Header("conventions"); })
      .def_property_readonly(
          "header",
          [](const PyCollection& c) { return ToPython(c.data().header_json()); },
          "collection.json without its frames")
      .def_property_readonly(
          "metadata_variants",
          [](const PyCollection& c) { return c.Header("metadata"); },
          "collection.json's metadata variants: dicts with file, perturbed, description")
      .def_property_readonly(
          "metadata_variant",
          [](const PyCollection& c) -> py::object {
            const std::string& file = c.data().metadata_variant();
            if (file.empty()) return py::none();
            return py::str(file);
          },
          "the `file` of the variant Frame.metadata reads (lsds.open's `metadata`)")
      .def_property_readonly("threads", [](const PyCollection& c) { return c.data().threads(); })
      .def("__repr__", [](const PyCollection& c) {
        return "<lsds.Collection " + c.data().reader().root().string() + ": " +
               std::to_string(c.Size()) + " frames>";
      });
}

}  // namespace

void RegisterCollection(py::module_& m) {
  RegisterCamera(m);
  RegisterBundle(m);
  RegisterFrame(m);
  RegisterCollectionClass(m);
  m.def("open",
        &Open,
        py::arg("path"),
        py::arg("threads") = 1,
        py::kw_only(),
        py::arg("metadata") = py::none(),
        "Opens the collection folder `path` (holding collection.json). `threads`: the TBB "
        "threads one layer decode may use; 1 (the default) starts no thread, so the process may "
        "fork afterwards (DataLoader workers). `metadata`: the metadata variant Frame.metadata "
        "reads, a `file` of Collection.metadata_variants (e.g. 'metadata.perturbed-7.json' of "
        "`lsds perturb-metadata`); None: the truth metadata.");
}

}  // namespace lsds::python
