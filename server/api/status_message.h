// GetStatus's answer: the pipeline's report and the black box's rings as the API's message.
#pragma once

#include <vector>

#include "omniview/v1/omniview.pb.h"
#include "server/blackbox/black_box.h"
#include "server/pipeline/pipeline_report.h"

namespace omniview {

v1::Status status_message(const PipelineReport& pipeline, const std::vector<BlackBoxRingReport>& rings);

}  // namespace omniview
