"""The world's visual geometry (robot and environment bodies) and where it is drawn."""

from __future__ import annotations

import warnings

import numpy as np

ROOT = "world"


def body_path(body: str) -> str:
    """Meshcat path of a body's node; its geometry objects are children of it."""
    return f"{ROOT}/visuals/{body}"


class WorldGeometry:
    """Every visual geometry of a world, loaded through pinocchio's Meshcat visualiser.

    The robot's links and the environment bodies (fixed frames of the world model)
    are all geometry objects of ``world.visual_model``. Each geometry object is drawn
    at ``world/visuals/BODY/GEOMETRY``, placed once in its body's node; a cycle then
    moves the body nodes only. Environment bodies moved by ``attach`` are drawn at the
    pose the run reports for them instead of their fixed placement.

    The kinematic model is copied when the object is made: a run re-parents the
    frames of the model it runs on, so make the viewer before the run.

    Attributes:
        model: The copy of the world's kinematic model.
        visual_model: The world's visual geometry.
    """

    def __init__(self, world):
        import pinocchio as pin

        self.model = world.model.copy()
        self.visual_model = world.visual_model
        self._data = self.model.createData()
        self._geometry: dict = {}
        for geometry in self.visual_model.geometryObjects:
            frame = self.model.frames[geometry.parentFrame]
            offset = (frame.placement.inverse() * geometry.placement).homogeneous
            scale = np.diag(np.append(np.asarray(geometry.meshScale, float), 1.0))
            self._geometry.setdefault(frame.name, {})[
                f"{body_path(frame.name)}/{geometry.name}"] = (offset, scale)
        self._frame_ids = {body: self.model.getFrameId(body, pin.FrameType.BODY)
                           for body in self._geometry}

    def body_names(self) -> list:
        """Names of the bodies that carry at least one visual geometry."""
        return list(self._geometry)

    def paths_of(self, body: str) -> list:
        """Meshcat paths of the geometry objects of ``body``."""
        return list(self._geometry.get(body, {}))

    def offsets(self) -> dict:
        """Geometry path -> 4x4 placement in its body's node [m], mesh scale included."""
        return {path: offset @ scale for shapes in self._geometry.values()
                for path, (offset, scale) in shapes.items()}

    def load(self, visualizer) -> None:
        """Send every geometry object (shape, material and place in its body's node).

        Args:
            visualizer: A ``meshcat.Visualizer`` on a server connection or a command log.
        """
        from pinocchio.visualize import MeshcatVisualizer

        class BodyNodes(MeshcatVisualizer):
            def getViewerNodeName(self, geometry_object, geometry_type):
                body = self.model.frames[geometry_object.parentFrame].name
                return f"{body_path(body)}/{geometry_object.name}"

        pinocchio_viewer = BodyNodes(self.model, None, self.visual_model)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            pinocchio_viewer.initViewer(viewer=visualizer)
            pinocchio_viewer.loadViewerModel(rootNodeName=ROOT)
        for path, offset in self.offsets().items():
            visualizer[path].set_transform(offset)

    def poses(self, q: np.ndarray, body_poses: dict | None = None) -> dict:
        """World pose of each body node at configuration ``q``.

        Args:
            q: The whole world's configuration (size ``model.nq``) [rad or m].
            body_poses: Body name -> 4x4 world pose of environment bodies moved by the
                run; these bodies are drawn there.

        Returns:
            Body node path -> 4x4 homogeneous matrix [m].
        """
        import pinocchio as pin

        pin.framesForwardKinematics(self.model, self._data, np.asarray(q, dtype=float))
        moved = body_poses or {}
        return {body_path(body): (np.asarray(moved[body], dtype=float) if body in moved
                                  else self._data.oMf[frame_id].homogeneous)
                for body, frame_id in self._frame_ids.items()}

    def body_position(self, body: str) -> np.ndarray:
        """Position [m] of ``body`` in the world at the configuration of the last
        :meth:`poses` call."""
        import pinocchio as pin

        frame_id = self.model.getFrameId(body, pin.FrameType.BODY)
        return pin.updateFramePlacement(self.model, self._data, frame_id).translation.copy()

    def corners(self, q: np.ndarray) -> np.ndarray:
        """Corners of every geometry's bounding box at ``q``, in the world frame.

        Args:
            q: The whole world's configuration (size ``model.nq``).

        Returns:
            An ``(8 * geometries) x 3`` array [m].
        """
        poses = self.poses(q)
        corners = []
        for geometry in self.visual_model.geometryObjects:
            body = self.model.frames[geometry.parentFrame].name
            offset, _ = self._geometry[body][f"{body_path(body)}/{geometry.name}"]
            shape = geometry.geometry      # coal shapes carry the mesh scale already
            shape.computeLocalAABB()
            low, high = np.asarray(shape.aabb_local.min_), np.asarray(shape.aabb_local.max_)
            box = np.array([[x, y, z, 1.0] for x in (low[0], high[0])
                            for y in (low[1], high[1]) for z in (low[2], high[2])])
            corners.append((poses[body_path(body)] @ offset @ box.T).T[:, :3])
        return np.vstack(corners)
