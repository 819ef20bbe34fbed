#include "libs/exr/encoder_settings.h"

#include <thread>

#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfThreading.h>

namespace lsds::exr {

void SetEncoderSettings(int zip_level, int threads) {
  Imf::setDefaultZipCompressionLevel(zip_level);
  Imf::setGlobalThreadCount(threads > 0 ? threads
                                        : static_cast<int>(std::thread::hardware_concurrency()));
}

}  // namespace lsds::exr
