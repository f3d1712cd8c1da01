"""The world's visual geometry (robot and environment bodies) and where it is drawn."""

from __future__ import annotations

import warnings

import numpy as np

ROOT = "world"


class WorldGeometry:
    """Every visual geometry of a world, loaded through pinocchio's Meshcat visualiser.

    The robot's links and the environment bodies (fixed frames of the world model)
    are all geometry objects of ``world.visual_model``; each is drawn at the Meshcat
    path ``world/visuals/GEOMETRY``. Environment bodies moved by ``attach`` are drawn
    at the pose the run reports for them instead of their fixed placement.
    """

    def __init__(self, world):
        import pinocchio as pin

        self.model = world.model
        self.visual_model = world.visual_model
        self._data = self.model.createData()
        self._geometry_data = pin.GeometryData(self.visual_model)
        objects = self.visual_model.geometryObjects
        self.paths = tuple(f"{ROOT}/visuals/{g.name}" for g in objects)
        self._scales = tuple(np.diag(np.append(np.asarray(g.meshScale, float), 1.0))
                             for g in objects)
        self._body_offsets: dict = {}
        for index, geometry in enumerate(objects):
            frame = self.model.frames[geometry.parentFrame]
            offset = (frame.placement.inverse() * geometry.placement).homogeneous
            self._body_offsets.setdefault(frame.name, []).append((index, offset))

    def body_names(self) -> list:
        """Names of the bodies that carry at least one visual geometry."""
        return list(self._body_offsets)

    def paths_of(self, body: str) -> list:
        """Meshcat paths of the geometry attached to ``body``."""
        return [self.paths[index] for index, _ in self._body_offsets.get(body, [])]

    def load(self, visualizer) -> None:
        """Send every geometry object (shape and material) to ``visualizer``.

        Args:
            visualizer: A ``meshcat.Visualizer`` on a server connection or a command log.
        """
        from pinocchio.visualize import MeshcatVisualizer

        pinocchio_viewer = MeshcatVisualizer(self.model, None, self.visual_model)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            pinocchio_viewer.initViewer(viewer=visualizer)
            pinocchio_viewer.loadViewerModel(rootNodeName=ROOT)

    def poses(self, q: np.ndarray, body_poses: dict | None = None) -> dict:
        """World pose of each geometry at configuration ``q``.

        Args:
            q: The whole world's configuration (size ``model.nq``) [rad or m].
            body_poses: Body name -> 4x4 world pose of environment bodies moved by
                ``attach``; their geometry follows these poses.

        Returns:
            Meshcat path -> 4x4 homogeneous matrix [m], mesh scale included.
        """
        import pinocchio as pin

        pin.forwardKinematics(self.model, self._data, np.asarray(q, dtype=float))
        pin.updateGeometryPlacements(self.model, self._data, self.visual_model,
                                     self._geometry_data)
        placements = [p.homogeneous for p in self._geometry_data.oMg]
        for body, pose in (body_poses or {}).items():
            for index, offset in self._body_offsets.get(body, []):
                placements[index] = np.asarray(pose, dtype=float) @ offset
        return {path: placement @ scale
                for path, placement, scale in zip(self.paths, placements, self._scales)}

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
        for path, geometry in zip(self.paths, self.visual_model.geometryObjects):
            shape = geometry.geometry
            shape.computeLocalAABB()
            low, high = np.asarray(shape.aabb_local.min_), np.asarray(shape.aabb_local.max_)
            box = np.array([[x, y, z, 1.0] for x in (low[0], high[0])
                            for y in (low[1], high[1]) for z in (low[2], high[2])])
            corners.append((poses[path] @ box.T).T[:, :3])
        return np.vstack(corners)
