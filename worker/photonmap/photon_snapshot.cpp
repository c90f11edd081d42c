#include "photonmap/photon_snapshot.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "photonmap/byte_io.h"
#include "photonmap/kd_photon_map.h"

namespace farm {
namespace {

constexpr char kMagic[8] = {'P', 'F', 'P', 'H', 'O', 'T', 'O', 'N'};
constexpr std::uint32_t kVersion = 2;
constexpr std::uint64_t kIrradianceRecordSize = 4;
constexpr std::size_t kHeaderSize = 64;
constexpr std::size_t kDirEntrySize = 64;
constexpr std::uint64_t kAlignment = 64;
constexpr std::uint64_t kMaxPhotons = 0x7fffffff;

// A read-only private view of a whole file, unmapped on destruction.
class MappedFile {
 public:
  explicit MappedFile(const std::filesystem::path& file) {
    int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      throw std::runtime_error("photon snapshot " + file.string() + ": cannot open: " +
                               std::strerror(errno));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || st.st_size <= 0) {
      ::close(fd);
      throw std::runtime_error("photon snapshot " + file.string() + ": empty or unreadable");
    }
    size_ = static_cast<std::size_t>(st.st_size);
    // MAP_SHARED read-only: workers on one host that map the same cached snapshot share
    // its pages in the page cache instead of each holding a copy.
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_SHARED, fd, 0);
    ::close(fd);  // the mapping keeps the file alive
    if (p == MAP_FAILED) {
      throw std::runtime_error("photon snapshot " + file.string() + ": mmap failed: " +
                               std::strerror(errno));
    }
    data_ = p;
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile() { ::munmap(data_, size_); }

  std::string_view bytes() const { return {static_cast<const char*>(data_), size_}; }

 private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

[[noreturn]] void Fail(const std::string& what) {
  throw std::runtime_error("photon snapshot: " + what);
}

}  // namespace

struct SnapshotData {
  std::string owned;                  // FromBytes
  std::optional<MappedFile> mapped;   // Open
  std::optional<KdPhotonMap> maps[3]; // by kind - 1
  std::optional<KdPhotonMap> sites;   // the global map's first irradiance_count photons
};

namespace {

// Checks the layout (docs/photon-snapshot.md, "Readers") and creates the maps. Every
// offset is compared against the size before it is used, with divisions instead of
// multiplications where a forged count could overflow.
void ParseSnapshot(std::string_view b, SnapshotData& data) {
  if (reinterpret_cast<std::uintptr_t>(b.data()) % 4 != 0) Fail("buffer not 4-byte aligned");
  if (b.size() < kHeaderSize) Fail(std::to_string(b.size()) + " bytes is shorter than the header");
  if (std::memcmp(b.data(), kMagic, sizeof kMagic) != 0) Fail("bad magic (want PFPHOTON)");
  const char* h = b.data();
  if (auto v = byte_io::Load<std::uint32_t>(h + 8); v != kVersion) {
    Fail("unsupported version " + std::to_string(v));
  }
  if (byte_io::Load<std::uint32_t>(h + 12) != kHeaderSize) Fail("header_size is not 64");
  auto map_count = byte_io::Load<std::uint32_t>(h + 16);
  if (map_count > 3) Fail("map_count " + std::to_string(map_count) + " > 3");
  if (byte_io::Load<std::uint32_t>(h + 20) != kDirEntrySize) Fail("directory_entry_size is not 64");
  if (auto fs = byte_io::Load<std::uint64_t>(h + 24); fs != b.size()) {
    Fail("file_size " + std::to_string(fs) + " but " + std::to_string(b.size()) + " bytes");
  }
  std::uint64_t end = kHeaderSize + kDirEntrySize * map_count;
  if (end > b.size()) Fail("directory runs past the end");
  std::uint32_t previous_kind = 0;
  for (std::uint32_t i = 0; i < map_count; ++i) {
    const char* d = h + kHeaderSize + kDirEntrySize * i;
    const std::string m = "map " + std::to_string(i) + ": ";
    auto kind = byte_io::Load<std::uint32_t>(d);
    auto count = byte_io::Load<std::uint32_t>(d + 4);
    auto paths = byte_io::Load<std::uint64_t>(d + 8);
    auto offset = byte_io::Load<std::uint64_t>(d + 16);
    auto scale = byte_io::Load<float>(d + 48);
    if (!IsPhotonMapKind(kind)) Fail(m + "unknown kind " + std::to_string(kind));
    if (kind <= previous_kind) Fail(m + "kinds must increase");
    previous_kind = kind;
    if (count > kMaxPhotons) Fail(m + "photon_count over 2^31-1");
    if (offset % kAlignment != 0 || offset < end || offset > b.size()) {
      Fail(m + "offset " + std::to_string(offset) + " not 64-aligned after byte " +
           std::to_string(end));
    }
    if (count > (b.size() - offset) / kSnapshotRecordSize) {
      Fail(m + std::to_string(count) + " photons run past the end");
    }
    if (!(scale > 0) || !std::isfinite(scale)) Fail(m + "power_scale must be finite and > 0");
    if (byte_io::Load<std::uint32_t>(d + 52) != kSnapshotRecordSize) Fail(m + "record_size is not 20");
    const auto* records = reinterpret_cast<const unsigned char*>(h + offset);
    // One pass over the records: the search indexes by the axis field and must be able to
    // trust it; a NaN position would silently break the ordering.
    for (std::uint32_t j = 0; j < count; ++j) {
      const unsigned char* r = records + kSnapshotRecordSize * j;
      unsigned axis = byte_io::Load<std::uint16_t>(r + 18) & 3u;
      bool leaf = 2 * std::uint64_t(j) + 1 >= count;
      if (leaf != (axis == kLeafAxis)) {
        Fail(m + "photon " + std::to_string(j) + ": split axis " + std::to_string(axis) +
             (leaf ? " on a leaf" : " on an inner node"));
      }
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(byte_io::Load<float>(r + 4 * c))) {
          Fail(m + "photon " + std::to_string(j) + ": position not finite");
        }
      }
    }
    end = offset + kSnapshotRecordSize * std::uint64_t(count);
    data.maps[kind - 1].emplace(static_cast<PhotonMapKind>(kind), records, count, scale, paths);
  }
  // The irradiance section (version 2): present when irradiance_offset is not zero, one
  // 4-byte record per irradiance site (the global map's first photons) after the last
  // photon array.
  const auto irr_offset = byte_io::Load<std::uint64_t>(h + 32);
  const auto irr_count = byte_io::Load<std::uint32_t>(h + 40);
  const auto irr_scale = byte_io::Load<float>(h + 44);
  if (irr_offset == 0) {
    if (irr_count != 0 || irr_scale != 0) Fail("irradiance_count or scale set without a section");
  } else {
    if (!data.maps[0]) Fail("irradiance section without a global map");
    KdPhotonMap& global = *data.maps[0];
    // How many sites is the precompute's choice (IrradianceSites); any leading part of a
    // left-balanced tree is a kd-tree itself and is read correctly.
    if ((irr_count == 0 && global.size() > 0) || irr_count > global.size())
      Fail("irradiance_count " + std::to_string(irr_count) + " but the global map has " +
           std::to_string(global.size()) + " photons (want 1 to all of them)");
    if (!(irr_scale > 0) || !std::isfinite(irr_scale))
      Fail("irradiance_scale must be finite and > 0");
    if (irr_offset % kAlignment != 0 || irr_offset < end || irr_offset > b.size())
      Fail("irradiance_offset " + std::to_string(irr_offset) + " not 64-aligned after byte " +
           std::to_string(end));
    if (irr_count > (b.size() - irr_offset) / kIrradianceRecordSize)
      Fail("irradiance runs past the end");
    KdPhotonMap& sites = data.sites.emplace(global.prefix(irr_count));
    sites.set_irradiance(reinterpret_cast<const unsigned char*>(h + irr_offset), irr_scale);
    end = irr_offset + kIrradianceRecordSize * irr_count;
  }
  if (end != b.size()) Fail(std::to_string(b.size() - end) + " trailing bytes");
}

}  // namespace

PhotonSnapshot::PhotonSnapshot(std::unique_ptr<SnapshotData> data) : data_(std::move(data)) {}
PhotonSnapshot::PhotonSnapshot(PhotonSnapshot&&) noexcept = default;
PhotonSnapshot& PhotonSnapshot::operator=(PhotonSnapshot&&) noexcept = default;
PhotonSnapshot::~PhotonSnapshot() = default;

PhotonSnapshot PhotonSnapshot::Open(const std::filesystem::path& file) {
  auto data = std::make_unique<SnapshotData>();
  data->mapped.emplace(file);
  ParseSnapshot(data->mapped->bytes(), *data);
  return PhotonSnapshot(std::move(data));
}

PhotonSnapshot PhotonSnapshot::FromBytes(std::string bytes) {
  auto data = std::make_unique<SnapshotData>();
  data->owned = std::move(bytes);
  // std::string storage comes from operator new: aligned for any fundamental type.
  ParseSnapshot(data->owned, *data);
  return PhotonSnapshot(std::move(data));
}

const PhotonMap* PhotonSnapshot::irradiance_sites() const {
  return data_ && data_->sites ? &*data_->sites : nullptr;
}

const PhotonMap* PhotonSnapshot::map(PhotonMapKind kind) const {
  auto k = static_cast<std::uint32_t>(kind);
  if (!data_ || !IsPhotonMapKind(k) || !data_->maps[k - 1]) return nullptr;
  return &*data_->maps[k - 1];
}

}  // namespace farm
