"""What Gymnasium 1.4 has: every module, and the public names each binds at its top level.

A rewritten import must name something that exists: ``from gym.envs import atari`` must
not become ``from gymnasium.envs import atari`` (an ImportError). The imports rules ask
this table and report what is missing instead of renaming it. Generated from the
installed gymnasium 1.4.0 by ``python -m tests.gymnasium_api_table``;
``tests/test_import_targets.py`` checks it against the installed package.
"""

from __future__ import annotations

from functools import cache

GYMNASIUM_VERSION = "1.4.0"

# module -> its public top-level names (and submodules), space-separated
GYMNASIUM_API = {
    'gymnasium': 'ActionWrapper Env ObservationWrapper RewardWrapper Space VectorizeMode Wrapper core envs error experimental logger make make_vec notifications os pprint_registry register register_envs registry spaces spec sys utils vector wrappers',
    'gymnasium.core': 'ActType ActionWrapper Any Env EnvSpec Generic ObsType ObservationWrapper RecordConstructorArgs RenderFrame RewardWrapper Self SupportsFloat TYPE_CHECKING TypeAlias TypeVar Wrapper WrapperActType WrapperObsType WrapperSpec annotations deepcopy gymnasium np seeding spaces',
    'gymnasium.envs': 'Any box2d classic_control functional_jax_env make mujoco phys2d pprint_registry register registration registry spec tabular toy_text',
    'gymnasium.envs.box2d': 'BipedalWalker BipedalWalkerHardcore CarRacing LunarLander LunarLanderContinuous bipedal_walker car_dynamics car_racing lunar_lander',
    'gymnasium.envs.box2d.bipedal_walker': 'BipedalWalker BipedalWalkerHardcore BipedalWalkerHeuristics Box2D ContactDetector DependencyNotInstalled EzPickle FPS FRICTION HULL_FD HULL_POLY INITIAL_RANDOM LEG_DOWN LEG_FD LEG_H LEG_W LIDAR_RANGE LOWER_FD MOTORS_TORQUE SCALE SPEED_HIP SPEED_KNEE TERRAIN_GRASS TERRAIN_HEIGHT TERRAIN_LENGTH TERRAIN_STARTPAD TERRAIN_STEP TYPE_CHECKING VIEWPORT_H VIEWPORT_W a circleShape contactListener edgeShape env error fixtureDef gym heuristics math np polygonShape pygame revoluteJointDef spaces steps total_reward',
    'gymnasium.envs.box2d.car_dynamics': 'Any Box2D Car DependencyNotInstalled ENGINE_POWER FRICTION_LIMIT HULL_POLY1 HULL_POLY2 HULL_POLY3 HULL_POLY4 MUD_COLOR Particle SIZE WHEELPOS WHEEL_COLOR WHEEL_MOMENT_OF_INERTIA WHEEL_R WHEEL_W WHEEL_WHITE dataclass deque fixtureDef math np polygonShape revoluteJointDef',
    'gymnasium.envs.box2d.car_racing': 'BORDER BORDER_MIN_COUNT Box2D Car CarRacing DependencyNotInstalled EzPickle FPS FrictionDetector GRASS_DIM InvalidAction MAX_SHAPE_DIM PLAYFIELD SCALE STATE_H STATE_W TRACK_DETAIL_STEP TRACK_RAD TRACK_TURN_RATE TRACK_WIDTH VIDEO_H VIDEO_W WINDOW_H WINDOW_W ZOOM ZOOM_FOLLOW a contactListener env fixtureDef gfxdraw gym math np polygonShape pygame quit register_input spaces',
    'gymnasium.envs.box2d.lunar_lander': 'Box2D ContactDetector DependencyNotInstalled EzPickle FPS INITIAL_RANDOM LANDER_POLY LEG_AWAY LEG_DOWN LEG_H LEG_SPRING_TORQUE LEG_W LunarLander LunarLanderContinuous MAIN_ENGINE_POWER MAIN_ENGINE_Y_LOCATION SCALE SIDE_ENGINE_AWAY SIDE_ENGINE_HEIGHT SIDE_ENGINE_POWER TYPE_CHECKING VIEWPORT_H VIEWPORT_W circleShape contactListener demo_heuristic_lander edgeShape env error fixtureDef gym heuristic math np polygonShape pygame revoluteJointDef spaces step_api_compatibility',
    'gymnasium.envs.classic_control': 'AcrobotEnv CartPoleEnv Continuous_MountainCarEnv MountainCarEnv PendulumEnv acrobot cartpole continuous_mountain_car mountain_car pendulum utils',
    'gymnasium.envs.classic_control.acrobot': 'AcrobotEnv DependencyNotInstalled Env bound cos gym np pi rk4 sin spaces utils wrap',
    'gymnasium.envs.classic_control.cartpole': 'Any AutoresetMode CartPoleEnv CartPoleVectorEnv DependencyNotInstalled VectorEnv batch_space gym logger math np npt spaces utils',
    'gymnasium.envs.classic_control.continuous_mountain_car': 'Continuous_MountainCarEnv DependencyNotInstalled gym math np spaces utils',
    'gymnasium.envs.classic_control.mountain_car': 'DependencyNotInstalled MountainCarEnv gym math np spaces utils',
    'gymnasium.envs.classic_control.pendulum': 'DEFAULT_X DEFAULT_Y DependencyNotInstalled PendulumEnv angle_normalize gym np path spaces utils',
    'gymnasium.envs.classic_control.utils': 'SupportsFloat maybe_parse_reset_bounds verify_number_and_cast',
    'gymnasium.envs.functional_jax_env': 'ActType Any AutoresetMode EnvSpec FuncEnv FunctionalJaxEnv FunctionalJaxVectorEnv Generic ObsType PRNGKeyType StateType TypeAlias annotations batch_space gym jax jnp jrng seeding',
    'gymnasium.envs.mujoco': 'MujocoEnv MujocoRenderer ant_v4 ant_v5 half_cheetah_v4 half_cheetah_v5 hopper_v4 hopper_v5 humanoid_v4 humanoid_v5 humanoidstandup_v4 humanoidstandup_v5 inverted_double_pendulum_v4 inverted_double_pendulum_v5 inverted_pendulum_v4 inverted_pendulum_v5 mujoco_env mujoco_py_env mujoco_rendering pusher_v4 pusher_v5 reacher_v4 reacher_v5 swimmer_v4 swimmer_v5 utils walker2d_v4 walker2d_v5',
    'gymnasium.envs.mujoco.ant_v4': 'AntEnv Box DEFAULT_CAMERA_CONFIG MujocoEnv np utils',
    'gymnasium.envs.mujoco.ant_v5': 'AntEnv Box DEFAULT_CAMERA_CONFIG MujocoEnv np utils',
    'gymnasium.envs.mujoco.half_cheetah_v4': 'Box DEFAULT_CAMERA_CONFIG HalfCheetahEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.half_cheetah_v5': 'Box DEFAULT_CAMERA_CONFIG HalfCheetahEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.hopper_v4': 'Box DEFAULT_CAMERA_CONFIG HopperEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.hopper_v5': 'Box DEFAULT_CAMERA_CONFIG HopperEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.humanoid_v4': 'Box DEFAULT_CAMERA_CONFIG HumanoidEnv MujocoEnv mass_center np utils',
    'gymnasium.envs.mujoco.humanoid_v5': 'Box DEFAULT_CAMERA_CONFIG HumanoidEnv MujocoEnv mass_center np utils',
    'gymnasium.envs.mujoco.humanoidstandup_v4': 'Box DEFAULT_CAMERA_CONFIG HumanoidStandupEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.humanoidstandup_v5': 'Box DEFAULT_CAMERA_CONFIG HumanoidStandupEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.inverted_double_pendulum_v4': 'Box DEFAULT_CAMERA_CONFIG InvertedDoublePendulumEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.inverted_double_pendulum_v5': 'Box DEFAULT_CAMERA_CONFIG InvertedDoublePendulumEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.inverted_pendulum_v4': 'Box DEFAULT_CAMERA_CONFIG InvertedPendulumEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.inverted_pendulum_v5': 'Box DEFAULT_CAMERA_CONFIG InvertedPendulumEnv MujocoEnv np utils',
    'gymnasium.envs.mujoco.mujoco_env': 'DEFAULT_SIZE MujocoEnv NDArray Space error expand_model_path gym mujoco np path spaces',
    'gymnasium.envs.mujoco.mujoco_py_env': '',
    'gymnasium.envs.mujoco.mujoco_rendering': 'BaseRender MujocoRenderer OffScreenViewer Version WindowViewer glfw imageio mujoco np os time warn',
    'gymnasium.envs.mujoco.pusher_v4': 'Box DEFAULT_CAMERA_CONFIG MujocoEnv PusherEnv mujoco np utils',
    'gymnasium.envs.mujoco.pusher_v5': 'Box DEFAULT_CAMERA_CONFIG MujocoEnv PusherEnv np utils',
    'gymnasium.envs.mujoco.reacher_v4': 'Box DEFAULT_CAMERA_CONFIG MujocoEnv ReacherEnv np utils',
    'gymnasium.envs.mujoco.reacher_v5': 'Any Box DEFAULT_CAMERA_CONFIG Final MujocoEnv ReacherEnv np utils',
    'gymnasium.envs.mujoco.swimmer_v4': 'Box MujocoEnv SwimmerEnv np utils',
    'gymnasium.envs.mujoco.swimmer_v5': 'Box MujocoEnv SwimmerEnv np utils',
    'gymnasium.envs.mujoco.utils': 'MujocoEnv check_mujoco_reset_state get_state mujoco np set_state',
    'gymnasium.envs.mujoco.walker2d_v4': 'Box DEFAULT_CAMERA_CONFIG MujocoEnv Walker2dEnv np utils',
    'gymnasium.envs.mujoco.walker2d_v5': 'Box DEFAULT_CAMERA_CONFIG MujocoEnv Walker2dEnv np utils',
    'gymnasium.envs.phys2d': 'CartPoleFunctional CartPoleJaxEnv PendulumFunctional PendulumJaxEnv cartpole pendulum',
    'gymnasium.envs.phys2d.cartpole': 'ActType Any AutoresetMode CartPoleFunctional CartPoleJaxEnv CartPoleJaxVectorEnv CartPoleParams DependencyNotInstalled EzPickle FuncEnv FunctionalJaxEnv FunctionalJaxVectorEnv PRNGKeyType RenderStateType StateType TYPE_CHECKING TypeAlias annotations gym jax jnp np pygame struct',
    'gymnasium.envs.phys2d.pendulum': 'ActType Any AutoresetMode DependencyNotInstalled EzPickle FuncEnv FunctionalJaxEnv FunctionalJaxVectorEnv PRNGKeyType PendulumFunctional PendulumJaxEnv PendulumJaxVectorEnv PendulumParams RenderStateType StateType TYPE_CHECKING TypeAlias annotations gym jax jnp np path pygame struct',
    'gymnasium.envs.registration': 'Any AutoresetMode Callable ENV_ID_RE Enum Env EnvCreator EnvSpec Generator Iterable ModuleType Protocol Sequence VectorEnvCreator VectorizeMode Wrapper WrapperSpec annotations contextlib copy current_namespace dataclass dataclasses defaultdict difflib error field find_highest_version get_env_id gym importlib json load_env_creator logger make make_vec namespace parse_env_id pprint_registry re register register_envs registry spec warn',
    'gymnasium.envs.tabular': 'BlackJackJaxEnv CliffWalkingJaxEnv blackjack cliffwalking',
    'gymnasium.envs.tabular.blackjack': 'ActType AutoresetMode BlackJackJaxEnv BlackJackParams BlackjackFunctional DependencyNotInstalled EnvState EzPickle FuncEnv FunctionalJaxEnv HumanRendering NamedTuple PRNGKeyType RenderStateType SCREEN_SIZE StateType TYPE_CHECKING TypeAlias cmp dealer_stop deck draw_card draw_card_wrapper draw_hand draw_table env info is_bust is_natural jax jnp math notake np obs pygame random random_card score seeding spaces struct sum_hand take terminal usable_ace',
    'gymnasium.envs.tabular.cliffwalking': 'AGENT_OFFSET ART_CELL_SIZE ActType AutoresetMode CliffWalkingFunctional CliffWalkingJaxEnv DependencyNotInstalled EnvState EzPickle FLAG_OFFSET FuncEnv FunctionalJaxEnv HumanRendering LETTER_OFFSET NamedTuple PRNGKeyType RenderStateType TYPE_CHECKING TypeAlias annotations env fell_off info jax jnp np obs path pygame spaces terminal',
    'gymnasium.envs.toy_text': 'BlackjackEnv CliffWalkingEnv FrozenLakeEnv TaxiEnv blackjack cliffwalking frozen_lake taxi utils',
    'gymnasium.envs.toy_text.blackjack': 'ART_PIXEL BIG_DIGIT_GAP BlackjackEnv DEALER_CARD_POS DEALER_LABEL_POS DependencyNotInstalled FELT_COLOR HIDDEN_CARD_POS LABEL_DIGIT_GAP PLAYER_LABEL_POS PLAYER_SUM_TOP SCREEN_SIZE SMALL_DIGIT_GAP USABLE_ACE_TOP cmp deck draw_card draw_hand draw_table gym is_bust is_natural np os score spaces sum_hand usable_ace',
    'gymnasium.envs.toy_text.cliffwalking': 'AGENT_OFFSET ART_CELL_SIZE Any CliffWalkingEnv DOWN DependencyNotInstalled Env FLAG_OFFSET LEFT LETTER_OFFSET POSITION_MAPPING RIGHT StringIO UP categorical_sample closing gym np path spaces',
    'gymnasium.envs.toy_text.frozen_lake': 'DOWN DependencyNotInstalled Env FrozenLakeEnv LEFT MAPS RIGHT StringIO UP annotations categorical_sample closing generate_random_map gym is_valid np path seeding spaces utils',
    'gymnasium.envs.toy_text.taxi': 'Any BACKGROUND_POS CANVAS_COLOR CELL_SIZE DependencyNotInstalled Env GRID_ORIGIN HOUSE_POS MAP PASSENGER_OFFSET StringIO TAXI_H_OFFSET TAXI_V_OFFSET TaxiEnv WINDOW_SIZE categorical_sample closing gym np path spaces utils',
    'gymnasium.envs.toy_text.utils': 'categorical_sample np',
    'gymnasium.error': 'AlreadyPendingCallError ClosedEnvironmentError CustomSpaceError DependencyNotInstalled DeprecatedEnv DeprecatedWrapper Error InvalidAction InvalidBound InvalidMetadata InvalidProbability MissingArgument NameNotFound NamespaceNotFound NoAsyncCallError RegistrationError ResetNeeded UnregisteredEnv UnsupportedMode VersionNotFound',
    'gymnasium.experimental': 'functional',
    'gymnasium.experimental.functional': 'ActType Any Callable FuncEnv Generic ObsType Params RenderStateType RewardType Space StateType TerminalType TypeVar annotations np',
    'gymnasium.logger': 'ERROR WARN colorize deprecation error min_level warn warnings',
    'gymnasium.spaces': 'Box Dict Discrete Graph GraphInstance MultiBinary MultiDiscrete OneOf Sequence Space Text Tuple box dict discrete flatdim flatten flatten_space graph multi_binary multi_discrete oneof sequence space text tuple unflatten utils',
    'gymnasium.spaces.box': 'Any Box Iterable Literal Mapping NDArray Sequence Space TYPE_CHECKING TypeAlias TypeIs TypeVar annotations array_short_repr cast gym is_float_integer np overload',
    'gymnasium.spaces.dict': 'Any Dict Generic Iterable Iterator KeysView OrderedDict Sequence Space TYPE_CHECKING TypeVar annotations cast collections np typing',
    'gymnasium.spaces.discrete': 'Any Discrete Generic Iterable Literal Mapping MaskNDArray Space TYPE_CHECKING TypeVar annotations np overload',
    'gymnasium.spaces.graph': 'Any Box Discrete Graph GraphInstance Iterable Literal NDArray NamedTuple Sequence Space annotations gym np',
    'gymnasium.spaces.multi_binary': 'Any Iterable Literal MultiBinary NDArray Sequence Space annotations np',
    'gymnasium.spaces.multi_discrete': 'Any Discrete Generic Iterable Literal Mapping MaskNDArray MultiDiscrete NDArray Sequence Space TYPE_CHECKING TypeVar annotations gym np overload',
    'gymnasium.spaces.oneof': 'Any Generic Iterable OneOf Space TypeVar annotations np',
    'gymnasium.spaces.sequence': 'Any Iterable Literal NDArray Sequence Space annotations gym np',
    'gymnasium.spaces.space': 'Any Generic Iterable Mapping MaskNDArray Sequence Space TypeAlias TypeVar annotations np npt seeding',
    'gymnasium.spaces.text': 'Any NDArray Space Text alphanumeric annotations np',
    'gymnasium.spaces.tuple': 'Any Iterable Space Tuple TypeVar annotations np overload typing',
    'gymnasium.spaces.utils': 'Any Box Dict Discrete FlatType Graph GraphInstance MultiBinary MultiDiscrete NDArray OneOf Sequence Space T Text Tuple TypeAlias TypeVar annotations flatdim flatten flatten_space gym is_space_dtype_shape_equiv np op reduce singledispatch unflatten',
    'gymnasium.utils': 'EzPickle RecordConstructorArgs colorize env_checker env_match ezpickle passive_env_checker performance play record_constructor save_video seeding step_api_compatibility',
    'gymnasium.utils.colorize': 'Final Mapping color2num colorize',
    'gymnasium.utils.env_checker': 'Any check_action_space check_env check_observation_space check_reset_options check_reset_return_info_deprecation check_reset_return_type check_reset_seed_determinism check_returned_data_not_reused check_seed_deprecation check_space_limit check_step_determinism combinations data_equivalence data_shares_objects deepcopy env_render_passive_checker env_reset_passive_checker env_step_passive_checker gym inspect logger np spaces',
    'gymnasium.utils.env_match': 'check_environments_match data_equivalence gym np',
    'gymnasium.utils.ezpickle': 'Any EzPickle',
    'gymnasium.utils.passive_env_checker': 'Any Callable Env RenderFrame Space SupportsFloat TypeVar cast check_action_space check_obs check_observation_space check_space data_shares_objects env_data_reuse_passive_checker env_render_passive_checker env_reset_passive_checker env_step_passive_checker error inspect logger np overload partial spaces',
    'gymnasium.utils.performance': 'AutoresetMode Callable VectorEnv benchmark_init benchmark_render benchmark_step benchmark_vector_step gymnasium np time',
    'gymnasium.utils.play': 'ActType Any Axes Callable DependencyNotInstalled Env Event Figure Generic Iterable MissingKeysToAction PathCollection PlayPlot PlayableGame Surface TYPE_CHECKING TypeAlias TypeVar annotations deque display_arr gym logger matplotlib np play plt pygame',
    'gymnasium.utils.record_constructor': 'Any RecordConstructorArgs annotations deepcopy',
    'gymnasium.utils.save_video': 'Any Callable ImageSequenceClip annotations capped_cubic_video_schedule gym logger os save_video',
    'gymnasium.utils.seeding': 'RNG RandomNumberGenerator annotations error np np_random',
    'gymnasium.utils.step_api_compatibility': 'DoneStepType ObsType SupportsFloat TerminatedTruncatedStepType annotations convert_to_done_step_api convert_to_terminated_truncated_step_api np step_api_compatibility',
    'gymnasium.vector': 'AsyncVectorEnv AutoresetMode SyncVectorEnv VectorActionWrapper VectorEnv VectorObservationWrapper VectorRewardWrapper VectorWrapper async_vector_env sync_vector_env utils vector_env',
    'gymnasium.vector.async_vector_env': 'ActType AlreadyPendingCallError Any AsyncState AsyncVectorEnv AutoresetMode Callable ClosedEnvironmentError CloudpickleWrapper Connection CustomSpaceError Enum Env Generic Iterable NoAsyncCallError ObsType Queue RenderFrame Sequence Space SynchronizedArray VectorEnv annotations batch_differing_spaces batch_space clear_mpi_env_vars concatenate create_empty_array create_shared_memory deepcopy inspect is_space_dtype_shape_equiv iterate logger multiprocessing np npt read_from_shared_memory synchronize sys time traceback write_to_shared_memory',
    'gymnasium.vector.sync_vector_env': 'ActType Any AutoresetMode Callable Env Generic ObsType RenderFrame Sequence Space SyncVectorEnv VectorEnv annotations batch_differing_spaces batch_space cast concatenate create_empty_array deepcopy is_space_dtype_shape_equiv iterate np npt',
    'gymnasium.vector.utils': 'CloudpickleWrapper batch_differing_spaces batch_space clear_mpi_env_vars concatenate create_empty_array create_shared_memory iterate misc read_from_shared_memory shared_memory space_utils write_to_shared_memory',
    'gymnasium.vector.utils.misc': 'Callable CloudpickleWrapper Env Generator Generic TYPE_CHECKING TypeVar annotations clear_mpi_env_vars contextlib os',
    'gymnasium.vector.utils.shared_memory': 'Any Box CustomSpaceError Dict Discrete Graph Mapping ModuleType MultiBinary MultiDiscrete Never OneOf Sequence Space SynchronizedArray TYPE_CHECKING Text Tuple TypeAlias Unpack annotations c_bool c_int32 c_int64 c_uint8 create_shared_memory flatten mp np read_from_shared_memory singledispatch typecodes write_to_shared_memory',
    'gymnasium.vector.utils.space_utils': 'Any Box Callable CustomSpaceError Dict Discrete Graph GraphInstance Iterable Iterator Mapping MultiBinary MultiDiscrete Never OneOf Sequence Space TYPE_CHECKING Text Tuple TypeVar annotations batch_differing_spaces batch_space concatenate create_empty_array deepcopy iterate np singledispatch',
    'gymnasium.vector.vector_env': 'ActType Any ArrayType AutoresetMode Enum EnvSpec Generic ObsType RenderFrame Self TYPE_CHECKING TypeVar VectorActionWrapper VectorEnv VectorObservationWrapper VectorRewardWrapper VectorWrapper WrapperActType WrapperObsType annotations cast gym np seeding warn',
    'gymnasium.wrappers': 'AddRenderObservation AddWhiteNoise ArrayConversion AtariPreprocessing Autoreset ClipAction ClipReward DelayObservation DiscretizeAction DiscretizeObservation DtypeObservation FilterObservation FlattenObservation FrameStackObservation GrayscaleObservation HumanRendering JaxToNumpy JaxToTorch MaxAndSkipObservation NormalizeObservation NormalizeReward NumpyToTorch ObstructView OrderEnforcing PassiveEnvChecker RecordEpisodeStatistics RecordVideo RenderCollection RepeatAction RescaleAction RescaleObservation ReshapeObservation ResizeObservation StickyAction TimeAwareObservation TimeLimit TransformAction TransformObservation TransformReward array_conversion atari_preprocessing common importlib jax_to_numpy jax_to_torch numpy_to_torch rendering stateful_action stateful_observation stateful_reward transform_action transform_observation transform_reward utils vector',
    'gymnasium.wrappers.array_conversion': 'Any Array ArrayConversion DependencyNotInstalled Device Iterable Mapping ModuleType NoneType RenderFrame SupportsFloat Version WrapperActType WrapperObsType abc annotations array_conversion array_namespace functools gym importlib is_array_api_obj is_numpy_namespace module_name_to_namespace module_namespace np numbers to_device',
    'gymnasium.wrappers.atari_preprocessing': 'Any AtariPreprocessing Box SupportsFloat WrapperActType WrapperObsType annotations gym np',
    'gymnasium.wrappers.common': 'ActType Any Autoreset EnvSpec ObsType OrderEnforcing PassiveEnvChecker RecordEpisodeStatistics RenderFrame ResetNeeded SupportsFloat TYPE_CHECKING TimeLimit WrapperObsType annotations check_action_space check_observation_space deepcopy deque env_data_reuse_passive_checker env_render_passive_checker env_reset_passive_checker env_step_passive_checker gym logger time',
    'gymnasium.wrappers.jax_to_numpy': 'ActType ArrayConversion DependencyNotInstalled JaxToNumpy ObsType annotations array_conversion functools gym jax_to_numpy jnp module_namespace np numpy_to_jax',
    'gymnasium.wrappers.jax_to_torch': 'ArrayConversion DependencyNotInstalled Device JaxToTorch annotations array_conversion functools gym jax_to_torch jnp module_namespace torch torch_to_jax',
    'gymnasium.wrappers.numpy_to_torch': 'ArrayConversion DependencyNotInstalled Device NumpyToTorch annotations array_conversion functools gym module_namespace np numpy_to_torch torch torch_to_numpy',
    'gymnasium.wrappers.rendering': 'ActType AddWhiteNoise Any Callable DependencyNotInstalled Generic HumanRendering InvalidProbability ObsType ObstructView RecordVideo RenderCollection RenderFrame SupportsFloat annotations cast deepcopy error gc gym logger np os',
    'gymnasium.wrappers.stateful_action': 'ActType Any InvalidBound InvalidProbability ObsType RepeatAction StickyAction SupportsFloat WrapperActType WrapperObsType annotations gym np',
    'gymnasium.wrappers.stateful_observation': 'ActType Any Box DelayObservation Dict Final FrameStackObservation InvalidBound MaxAndSkipObservation NormalizeObservation ObsType RunningMeanStd SupportsFloat TimeAwareObservation Tuple WrapperActType WrapperObsType annotations batch_space concatenate create_empty_array create_zero_array deepcopy deque gym np spaces',
    'gymnasium.wrappers.stateful_reward': 'ActType Any InvalidBound NormalizeReward ObsType RunningMeanStd SupportsFloat annotations gym np',
    'gymnasium.wrappers.transform_action': 'ActType Box Callable ClipAction Discrete DiscretizeAction InvalidBound MultiDiscrete ObsType RescaleAction Space TransformAction WrapperActType annotations gym np rescale_box',
    'gymnasium.wrappers.transform_observation': 'ActType AddRenderObservation Any Callable DependencyNotInstalled DiscretizeObservation DtypeObservation FilterObservation Final FlattenObservation GrayscaleObservation ObsType RescaleObservation ReshapeObservation ResizeObservation Sequence TransformObservation WrapperObsType annotations gym np rescale_box spaces',
    'gymnasium.wrappers.transform_reward': 'ActType Callable ClipReward InvalidBound ObsType SupportsFloat TransformReward annotations gym np',
    'gymnasium.wrappers.utils': 'Box Callable CustomSpaceError Dict Discrete Graph GraphInstance MultiBinary MultiDiscrete OneOf RunningMeanStd Sequence Space Text Tuple TypeVar annotations create_zero_array gym np rescale_box singledispatch update_mean_var_count_from_moments',
    'gymnasium.wrappers.vector': 'ArrayConversion ClipAction ClipReward DictInfoToList DtypeObservation FilterObservation FlattenObservation GrayscaleObservation HumanRendering JaxToNumpy JaxToTorch NormalizeObservation NormalizeReward NumpyToTorch RecordEpisodeStatistics RecordVideo RescaleAction RescaleObservation ReshapeObservation ResizeObservation TYPE_CHECKING TransformAction TransformObservation TransformReward VectorizeTransformAction VectorizeTransformObservation VectorizeTransformReward array_conversion common dict_info_to_list importlib jax_to_numpy jax_to_torch numpy_to_torch rendering stateful_observation stateful_reward vectorize_action vectorize_observation vectorize_reward',
    'gymnasium.wrappers.vector.array_conversion': 'ActType Any ArrayConversion Device ModuleType ObsType VectorEnv VectorWrapper WrapperActType WrapperObsType annotations array_conversion gym module_name_to_namespace',
    'gymnasium.wrappers.vector.common': 'ActType Any AutoresetMode ObsType RecordEpisodeStatistics VectorEnv VectorWrapper annotations deque np npt time warn',
    'gymnasium.wrappers.vector.dict_info_to_list': 'ActType Any ArrayType DictInfoToList ObsType VectorEnv VectorWrapper annotations np',
    'gymnasium.wrappers.vector.jax_to_numpy': 'ArrayConversion DependencyNotInstalled JaxToNumpy VectorEnv annotations jnp np',
    'gymnasium.wrappers.vector.jax_to_torch': 'ArrayConversion Device JaxToTorch VectorEnv annotations jnp torch',
    'gymnasium.wrappers.vector.numpy_to_torch': 'ArrayConversion Device NumpyToTorch VectorEnv annotations np torch',
    'gymnasium.wrappers.vector.rendering': 'ActType Any ArrayType Callable DependencyNotInstalled HumanRendering ObsType RecordVideo RenderFrame Sequence TYPE_CHECKING VectorEnv VectorWrapper annotations deepcopy error gc gym logger np os pygame warn',
    'gymnasium.wrappers.vector.stateful_observation': 'ActType Any ArrayType AutoresetMode Box InvalidBound NormalizeObservation RunningMeanStd VectorEnv VectorObservationWrapper annotations batch_space gym np warn',
    'gymnasium.wrappers.vector.stateful_reward': 'ActType Any AutoresetMode InvalidBound NormalizeReward ObsType RunningMeanStd VectorEnv VectorWrapper annotations gym np',
    'gymnasium.wrappers.vector.vectorize_action': 'ActType Any ArrayType Callable ClipAction Env ObsType RescaleAction Space TransformAction VectorActionWrapper VectorEnv VectorizeTransformAction WrapperActType annotations batch_space concatenate create_empty_array deepcopy iterate np transform_action warn',
    'gymnasium.wrappers.vector.vectorize_observation': 'ActType Any ArrayType AutoresetMode Callable DtypeObservation Env FilterObservation FlattenObservation GrayscaleObservation ObsType RescaleObservation ReshapeObservation ResizeObservation Sequence Space TransformObservation VectorEnv VectorObservationWrapper VectorizeTransformObservation WrapperObsType annotations batch_space concatenate create_empty_array deepcopy iterate np transform_observation warn',
    'gymnasium.wrappers.vector.vectorize_reward': 'ActType Any ArrayType Callable ClipReward Env ObsType TransformReward TypeVar VectorEnv VectorRewardWrapper VectorizeTransformReward annotations np transform_reward',
}


def module_exists(module: str) -> bool:
    return module in GYMNASIUM_API


@cache
def names_of(module: str) -> frozenset[str]:
    return frozenset(GYMNASIUM_API.get(module, "").split())


def has_name(module: str, name: str) -> bool:
    """``from module import name`` works in Gymnasium 1.4 (a name it binds or a submodule)."""
    return name in names_of(module)


@cache
def submodules_of(module: str) -> tuple[str, ...]:
    """The modules of Gymnasium 1.4 directly below ``module``."""
    depth = module.count(".") + 1
    return tuple(m for m in GYMNASIUM_API if m.startswith(module + ".") and m.count(".") == depth)
