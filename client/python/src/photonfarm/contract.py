"""The limits the SDK obeys, read from the contract's options in the generated modules
(blob.proto's rpc_limits, scene.proto's scene_limits) rather than restated here."""

from renderfarm.v1 import blob_pb2, rules_pb2, scene_pb2

RPC = blob_pb2.DESCRIPTOR.GetOptions().Extensions[rules_pb2.rpc_limits]
"""max_message_bytes, max_upload_chunk_bytes, max_blob_bytes, ..."""

SCENE = scene_pb2.Scene.DESCRIPTOR.GetOptions().Extensions[rules_pb2.scene_limits]
"""max_asset_bytes, max_film_pixels, ..."""
