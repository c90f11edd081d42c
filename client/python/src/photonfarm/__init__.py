"""photonfarm: the Python SDK of the photonfarm render farm.

    import photonfarm
    with photonfarm.Client("localhost:7070", token="...") as farm:
        job = farm.submit("scenes/test-small.json")
        for event in farm.watch(job.id):
            print(event.kind_name, event.job.state if event.job else event.task.id)
        image = farm.fetch(job.id)
        indirect = image.layers["indirect"]  # numpy float32, (height, width, 3)

The protobuf and gRPC modules generated from the farm's proto/ folder are in the package
renderfarm.v1 (job_pb2, scene_pb2, ...).
"""

from .client import Client
from .errors import FarmError
from .exr import Image
from .jobs import JobEvent, Report, Round

__all__ = ["Client", "FarmError", "Image", "JobEvent", "Report", "Round"]
