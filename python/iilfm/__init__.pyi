from ._iilfm import Cloud as Cloud
from ._iilfm import InputError as InputError
from ._iilfm import Marker as Marker
from ._iilfm import Pipeline as Pipeline
from ._iilfm import Pose as Pose
from ._iilfm import Result as Result
from ._iilfm import read_cloud as read_cloud
from ._iilfm import simulate as simulate
